#include "app/auto_choice.h"

#include <fmt/format.h>

#include <bit>
#include <nlohmann/json.hpp>

#include "input_error.h"

namespace vkpath::app {
namespace {

constexpr std::pair<KnobSource, const char*> SOURCE_NAMES[] = {
    {KnobSource::Measured, "measured"},
    {KnobSource::Given, "given"},
    {KnobSource::NotMeasured, "not measured"},
    {KnobSource::DoesNotApply, "does not apply"},
};

// "2^20" for powers of two, else the number.
std::string pathCount(uint32_t paths) {
    return std::has_single_bit(paths) ? fmt::format("2^{}", std::countr_zero(paths))
                                      : std::to_string(paths);
}

// " (given)" etc. after a knob's value; nothing for a measured one.
std::string sourceNote(const AutoChoice& c, const std::string& knob) {
    for (const auto& [name, source] : c.sources)
        if (name == knob && source != KnobSource::Measured)
            return fmt::format(" ({})", knobSourceName(source));
    return "";
}

}  // namespace

const char* knobSourceName(KnobSource source) {
    for (const auto& [s, name] : SOURCE_NAMES)
        if (s == source) return name;
    return "?";
}

std::string describeAutoChoice(const AutoChoice& c) {
    std::string line = fmt::format(
        "auto: rr-depth {}{}, light samples {}{}, sampler {}{}, light sampler {}{}, guide {}{}",
        c.rouletteDepth, sourceNote(c, "rr-depth"), c.lightSamples, sourceNote(c, "light-samples"),
        c.sampler, sourceNote(c, "sampler"), c.lightSampler, sourceNote(c, "light-sampler"),
        c.guideSpheres, sourceNote(c, "guide-spheres"));
    if (!c.kernel.empty())
        line += fmt::format(", kernel {}{}, paths {}{}", c.kernel, sourceNote(c, "kernel"),
                            pathCount(c.pathsInFlight), sourceNote(c, "paths-in-flight"));
    if (c.resumed) return line + " (the checkpoint's choice)";
    if (c.pilotRenders == 0) return line + " (no pilots: " + c.skipped + ")";
    const double share = c.budgetSeconds > 0 ? 100 * c.pilotSeconds / c.budgetSeconds : 0;
    line += fmt::format(" (pilots {:.3g} s, {:.1f}% of the budget {:.3g} s, {} renders{}",
                        c.pilotSeconds, share, c.budgetSeconds, c.pilotRenders,
                        c.pilotFilm.empty() ? "" : " at " + c.pilotFilm);
    line += fmt::format("; their setup and pipelines {:.3g} s more", c.setupSeconds);
    if (!c.skipped.empty()) line += "; " + c.skipped;
    return line + ")";
}

std::string autoChoiceJson(const AutoChoice& c) {
    nlohmann::ordered_json record;
    record["rr-depth"] = c.rouletteDepth;
    record["light-samples"] = c.lightSamples;
    record["sampler"] = c.sampler;
    record["light-sampler"] = c.lightSampler;
    record["guide-spheres"] = std::stod(fmt::format("{}", c.guideSpheres));
    record["kernel"] = c.kernel.empty() ? "none" : c.kernel;
    record["paths-in-flight"] = c.pathsInFlight;
    nlohmann::ordered_json sources;
    for (const auto& [knob, source] : c.sources) sources[knob] = knobSourceName(source);
    record["sources"] = sources;
    record["pilot-seconds"] = c.pilotSeconds;
    record["setup-seconds"] = c.setupSeconds;
    record["budget-seconds"] = c.budgetSeconds;
    record["pilot-renders"] = c.pilotRenders;
    record["pilot-film"] = c.pilotFilm;
    if (!c.skipped.empty()) record["skipped"] = c.skipped;
    return record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

AutoChoice parseAutoChoice(const std::string& json, const std::string& what) {
    const nlohmann::json record = nlohmann::json::parse(json, nullptr, false);
    auto bad = [&](const char* why) {
        return InputError(fmt::format("{}: its --auto choice is not readable: {}", what, why));
    };
    if (!record.is_object()) throw bad("not a JSON object");
    AutoChoice c;
    try {
        c.rouletteDepth = record.at("rr-depth").get<uint32_t>();
        c.lightSamples = record.at("light-samples").get<uint32_t>();
        c.sampler = record.at("sampler").get<std::string>();
        c.lightSampler = record.value("light-sampler", std::string("auto"));
        c.guideSpheres = record.at("guide-spheres").get<float>();
        c.kernel = record.at("kernel").get<std::string>();
        if (c.kernel == "none") c.kernel.clear();
        c.pathsInFlight = record.at("paths-in-flight").get<uint32_t>();
        for (const auto& [knob, name] : record.at("sources").items())
            for (const auto& [source, sourceName] : SOURCE_NAMES)
                if (name.get<std::string>() == sourceName) c.sources.emplace_back(knob, source);
        c.pilotSeconds = record.value("pilot-seconds", 0.0);
        c.setupSeconds = record.value("setup-seconds", 0.0);
        c.budgetSeconds = record.value("budget-seconds", 0.0);
        c.pilotRenders = record.value("pilot-renders", 0u);
        c.pilotFilm = record.value("pilot-film", std::string());
        c.skipped = record.value("skipped", std::string());
    } catch (const nlohmann::json::exception&) {
        throw bad("a field is missing or of the wrong type");
    }
    if (c.sampler != "sobol" && c.sampler != "independent") throw bad("an unknown sampler");
    if (!wavefront::parseLightSampling(c.lightSampler)) throw bad("an unknown light sampler");
    if (!c.kernel.empty() && c.kernel != "megakernel" && c.kernel != "wavefront")
        throw bad("an unknown kernel form");
    return c;
}

void applyAutoChoice(const AutoChoice& c, RenderOptions& o) {
    o.rouletteDepth = c.rouletteDepth;
    o.lightSamples = c.lightSamples;
    o.sampler = c.sampler;
    o.lightSampler = c.lightSampler;
    o.guideSpheres = c.guideSpheres;
    if (!c.kernel.empty()) o.kernel = c.kernel;
    if (c.pathsInFlight > 0) o.pathsInFlight = c.pathsInFlight;
}

}  // namespace vkpath::app
