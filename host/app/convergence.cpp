#include "app/convergence.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <limits>

#include "input_error.h"

namespace vkpath::app {
namespace {

std::vector<std::string> splitCommas(const std::string& text) {
    std::vector<std::string> parts;
    size_t begin = 0;
    for (;;) {
        const size_t comma = text.find(',', begin);
        parts.push_back(text.substr(begin, comma - begin));
        if (comma == std::string::npos) return parts;
        begin = comma + 1;
    }
}

std::optional<uint32_t> parseUnsigned(const std::string& text) {
    uint32_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || text.empty())
        return std::nullopt;
    return value;
}

uint32_t unsignedValue(const char* knob, const std::string& value) {
    const auto v = parseUnsigned(value);
    if (!v) throw InputError(fmt::format("{}: '{}' is not a whole number", knob, value));
    return *v;
}

// A knob that is `off` (0) or a number that `valid` accepts (`what` says
// which numbers, for the error).
float offOrNumber(const char* knob, const std::string& value, const char* what,
                  bool (*valid)(float)) {
    if (value == "off") return 0;
    float number = 0;
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), number);
    if (error != std::errc() || end != value.data() + value.size() || !valid(number))
        throw InputError(fmt::format("{}: '{}' is neither off nor {}", knob, value, what));
    return number;
}

// The knob table. Each row: the name --sweep takes, the values it accepts and
// how one sets RenderSettings.
const std::vector<Knob> KNOBS = {
    {"max-depth", "whole numbers",
     [](wavefront::RenderSettings& s, const std::string& v) {
         s.maxDepth = unsignedValue("max-depth", v);
     },
     true},
    {"light-samples", "whole numbers",
     [](wavefront::RenderSettings& s, const std::string& v) {
         s.lightSamples = unsignedValue("light-samples", v);
     },
     false},
    {"rr-depth", "whole numbers",
     [](wavefront::RenderSettings& s, const std::string& v) {
         s.rouletteDepth = unsignedValue("rr-depth", v);
     },
     false},
    {"sampler", "independent or sobol",
     [](wavefront::RenderSettings& s, const std::string& v) {
         const auto sampler = wavefront::parseSampler(v);
         if (!sampler)
             throw InputError(fmt::format("sampler: '{}' is neither independent nor sobol", v));
         s.sampler = *sampler;
     },
     false},
    {"light-sampler", "auto, power or tree",
     [](wavefront::RenderSettings& s, const std::string& v) {
         const auto sampling = wavefront::parseLightSampling(v);
         if (!sampling)
             throw InputError(fmt::format("light-sampler: '{}' is none of auto, power, tree", v));
         s.lightSampling = *sampling;
     },
     false},
    {"clamp", "off or numbers > 0",
     [](wavefront::RenderSettings& s, const std::string& v) {
         s.clampRadiance = offOrNumber("clamp", v, "a number > 0",
                                       [](float c) { return c > 0 && std::isfinite(c); });
     },
     true},
    {"guide-spheres", "off or fractions in (0, 1)",
     [](wavefront::RenderSettings& s, const std::string& v) {
         s.guideFraction = offOrNumber("guide-spheres", v, "a number in (0, 1)",
                                       [](float f) { return f > 0 && f < 1; });
     },
     false},
    {"regularize", "off or GGX alphas in (0, 1]",
     [](wavefront::RenderSettings& s, const std::string& v) {
         s.regularize = offOrNumber("regularize", v, "a number in (0, 1]",
                                    [](float a) { return a > 0 && a <= 1; });
     },
     true},
};

}  // namespace

std::vector<uint32_t> parseSppList(const std::string& text) {
    std::vector<uint32_t> list;
    for (const std::string& part : splitCommas(text)) {
        const auto v = parseUnsigned(part);
        if (!v || *v == 0 || (!list.empty() && *v <= list.back()))
            throw InputError(fmt::format(
                "'{}' is not a list of increasing sample counts >= 1, e.g. 1,2,4,8", text));
        list.push_back(*v);
    }
    return list;
}

const std::vector<Knob>& knobs() {
    return KNOBS;
}

Sweep parseSweep(const std::string& text) {
    const size_t equals = text.find('=');
    std::string names;
    for (const Knob& k : KNOBS) names += (names.empty() ? "" : ", ") + std::string(k.name);
    if (equals == std::string::npos)
        throw InputError(fmt::format("'{}' is not KNOB=v1,v2,... (knobs: {})", text, names));
    const std::string name = text.substr(0, equals);
    Sweep sweep;
    for (const Knob& k : KNOBS)
        if (name == k.name) sweep.knob = &k;
    if (!sweep.knob) throw InputError(fmt::format("unknown knob '{}' (knobs: {})", name, names));
    sweep.values = splitCommas(text.substr(equals + 1));
    for (const std::string& value : sweep.values) {
        if (value.empty())
            throw InputError(
                fmt::format("{}: empty value in '{}' ({})", name, text, sweep.knob->values));
        wavefront::RenderSettings check;
        sweep.knob->apply(check, value);
    }
    return sweep;
}

std::optional<double> timeToRelMse(const std::vector<Checkpoint>& curve, double target) {
    for (size_t i = 0; i < curve.size(); ++i) {
        if (!(curve[i].relMse <= target)) continue;
        if (i == 0) return curve[0].wallSeconds;
        const Checkpoint& a = curve[i - 1];
        const Checkpoint& b = curve[i];
        // Log-log interpolation needs positive values; a zero error or time
        // (an exact match, a timer too coarse) falls back to the later checkpoint.
        if (!(a.wallSeconds > 0 && b.wallSeconds > 0 && a.relMse > 0 && b.relMse > 0))
            return b.wallSeconds;
        const double t =
            (std::log(target) - std::log(a.relMse)) / (std::log(b.relMse) - std::log(a.relMse));
        return std::exp(std::log(a.wallSeconds) +
                        t * (std::log(b.wallSeconds) - std::log(a.wallSeconds)));
    }
    return std::nullopt;
}

double efficiency(const std::vector<Checkpoint>& curve) {
    if (curve.empty()) return 0;
    const double cost = curve.back().wallSeconds * curve.back().relMse;
    return cost > 0 ? 1 / cost : std::numeric_limits<double>::infinity();
}

}  // namespace vkpath::app
