// `vkpath render SCENE`: the wavefront path tracer (or, with --device cpu, the
// CPU reference running the same math), start to EXR.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "app/commands.h"
#include "app/film_size.h"
#include "app/render_options.h"
#include "image/image.h"
#include "image/statistics.h"
#include "input_error.h"
#include "reference/reference_renderer.h"
#include "vk/context.h"
#include "wavefront/renderer.h"

namespace vkpath::app {
namespace {

// The shared flags (render_options.h) and what render does with its one image.
struct RenderCommandOptions : RenderOptions {
    std::string output = "out/render.exr";
    std::string png;
    std::optional<uint32_t> spp;  // unset: 16, or with --time-budget as many as the budget allows
    std::string samples;          // --samples FIRST:COUNT (instead of -s): that range of sample indices
    std::optional<double> timeBudget;
    float exposure = 0.0f;
    std::vector<std::string> aovs;
    bool timings = false;
};

void ensureParent(const std::filesystem::path& path) {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
}

// With a time budget the bar measures time, unless the sample count runs out first.
void printProgress(const wavefront::RenderProgress& p, uint64_t pixels, std::optional<double> timeBudget) {
    double fraction = p.samplesTotal ? double(p.samplesDone) / p.samplesTotal : 1.0;
    if (timeBudget && *timeBudget > 0) fraction = std::min(1.0, std::max(fraction, p.seconds / *timeBudget));
    const int width = 30;
    const int filled = int(fraction * width);
    const double mpaths = p.seconds > 0 ? double(p.samplesDone) * pixels / p.seconds * 1e-6 : 0.0;
    const double eta = fraction > 0 ? p.seconds * (1 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "\r[%.*s%*s] %u/%u spp  %.2f Mpaths/s  ETA %.1f s ", filled,
                 "##############################", width - filled, "", p.samplesDone, p.samplesTotal, mpaths, eta);
}

// Either renderer, with a progress bar when stderr is a terminal. Also
// measures the CPU time the whole process spent rendering (every thread,
// lavapipe's included), which on a shared machine varies far less than the
// wall clock.
template <typename Renderer>
wavefront::RenderResult renderWithProgress(Renderer& renderer, const wavefront::SampleRange& samples,
                                           const FilmSize& film, std::optional<double> timeBudget, double& cpuSeconds) {
    const bool terminal = isatty(STDERR_FILENO);
    const uint64_t pixels = uint64_t(film.width) * film.height;
    const std::clock_t start = std::clock();
    auto result = renderer.render(samples, [&](const wavefront::RenderProgress& p) {
        if (terminal) printProgress(p, pixels, timeBudget);
    });
    cpuSeconds = double(std::clock() - start) / CLOCKS_PER_SEC;
    if (terminal) std::fprintf(stderr, "\n");
    return result;
}

// "FIRST:COUNT" of --samples; throws InputError naming the flag.
wavefront::SampleRange parseSampleRange(const std::string& text) {
    const size_t colon = text.find(':');
    uint64_t first = 0, count = 0;
    auto number = [&](const std::string& digits, uint64_t& value) {
        if (digits.empty() || digits.size() > 10 || digits.find_first_not_of("0123456789") != std::string::npos)
            return false;
        value = std::stoull(digits);
        return value <= UINT32_MAX;
    };
    if (colon == std::string::npos || !number(text.substr(0, colon), first) || !number(text.substr(colon + 1), count) ||
        count == 0)
        throw InputError(fmt::format("--samples {}: expected FIRST:COUNT, two whole numbers, COUNT at least 1", text));
    return {uint32_t(first), uint32_t(count)};
}

// The EXR (with metadata), the AOVs beside it and the PNG preview.
void writeOutputs(const RenderCommandOptions& o, const wavefront::SampleRange& samples,
                  const wavefront::RenderResult& result, const std::string& device) {
    const std::filesystem::path output(o.output);
    ensureParent(output);
    const RenderIdentity identity = renderIdentity(o);
    const image::Metadata metadata = {
        {"vkpath:version", VKPATH_VERSION},
        {"vkpath:spp", std::to_string(result.samplesPerPixel)},
        {"vkpath:firstSample", std::to_string(samples.first)},
        {"vkpath:sceneHash", identity.sceneHash},
        {"vkpath:settings", identity.settings},
        {"vkpath:seed", std::to_string(o.seed)},
        {"vkpath:sampler", o.sampler},
        {"vkpath:maxDepth", std::to_string(o.maxDepth)},
        {"vkpath:lightSamples", std::to_string(o.lightSamples)},
        {"vkpath:rrDepth", std::to_string(o.rouletteDepth)},
        {"vkpath:device", device},
        {"vkpath:renderSeconds", fmt::format("{:.6f}", result.seconds)},
        {"vkpath:nonFiniteSamples", std::to_string(result.nonFiniteSamples)},
        {"vkpath:fireflySamples", std::to_string(result.fireflySamples)},
        {"vkpath:rejectedLightSamples", std::to_string(result.rejectedLightSamples)},
        {"vkpath:clamp", o.clamp > 0 ? fmt::format("{}", o.clamp) : std::string("off")},
        {"vkpath:scene", o.scene}};
    image::writeExr(output, result.image, metadata);
    std::printf("%s\n", output.string().c_str());
    for (const std::string& aov : o.aovs) {
        const auto path = image::aovPath(output, aov);
        image::writeExr(path, result.varianceOfMean, metadata);
        std::printf("%s\n", path.string().c_str());
    }
    if (!o.png.empty()) {
        ensureParent(o.png);
        image::writePng(o.png, result.image, o.exposure);
        std::printf("%s\n", o.png.c_str());
    }
}

// `deviceMs`: the GPU's summed stage times (none on the CPU, whose waves are passes over the image).
void printSummary(const FilmSize& film, const wavefront::RenderResult& result, std::optional<double> deviceMs,
                  double cpuSeconds, const std::string& device, bool clamped) {
    const double mpaths = result.seconds > 0 ? result.paths / result.seconds * 1e-6 : 0;
    const double mpathsPerCpuSecond = cpuSeconds > 0 ? result.paths / cpuSeconds * 1e-6 : 0;
    const double mrays = result.seconds > 0 ? result.rays.total() / result.seconds * 1e-6 : 0;
    const std::string deviceTime = deviceMs ? fmt::format(" (device {:.3f} s)", *deviceMs * 1e-3) : "";
    std::fprintf(stderr,
                 "rendered %ux%u at %u spp in %.3f s%s: %.3f Mpaths/s (%.3f per CPU second), %.3f Mrays/s "
                 "(%llu closest-hit, %llu shadow), %u %s of %u paths, %llu NaN/Inf samples dropped, %llu fireflies%s, "
                 "%llu light samples of pdf 0 skipped, on %s\n",
                 film.width, film.height, result.samplesPerPixel, result.seconds, deviceTime.c_str(), mpaths,
                 mpathsPerCpuSecond, mrays, (unsigned long long)result.rays.closest,
                 (unsigned long long)result.rays.shadow, result.waves, deviceMs ? "waves" : "passes", result.pathsInFlight,
                 (unsigned long long)result.nonFiniteSamples, (unsigned long long)result.fireflySamples,
                 clamped ? " (clamped)" : "", (unsigned long long)result.rejectedLightSamples, device.c_str());
}

int runRender(const GlobalOptions& global, const RenderCommandOptions& o) {
    if (o.spp && *o.spp == 0) throw InputError("-s: samples per pixel must be at least 1");
    if (o.timeBudget && !(*o.timeBudget > 0)) throw InputError("--time-budget: seconds must be positive");
    if (!std::isfinite(o.exposure)) throw InputError("--exposure: stops must be a finite number");
    const FilmSize film = parseFilmSize(o.size);
    // A budget without -s renders until the budget is spent (sample indices
    // are 32-bit: at most 2^32 - 1 samples).
    if (o.spp && !o.samples.empty()) throw InputError("-s and --samples: give one (--samples FIRST:COUNT includes the count)");
    wavefront::SampleRange samples{0, o.spp ? *o.spp : o.timeBudget ? UINT32_MAX : 16};
    if (!o.samples.empty()) samples = parseSampleRange(o.samples);
    if (uint64_t(samples.first) + samples.count > (uint64_t(1) << 32))
        throw InputError(fmt::format("--samples {}:{}: sample indices beyond 2^32 - 1", samples.first, samples.count));
    const uint32_t spp = samples.count;
    wavefront::RenderSettings settings = renderSettings(o, spp);
    settings.timeBudgetSeconds = o.timeBudget;
    const scene::Scene scene = loadRenderScene(o);

    if (o.device == "cpu") {
        const reference::ReferenceRenderer renderer(scene, settings);
        const std::string device = fmt::format("CPU reference ({} threads)", renderer.threads());
        double cpuSeconds = 0;
        const auto result = renderWithProgress(renderer, samples, film, o.timeBudget, cpuSeconds);
        writeOutputs(o, samples, result, device);
        printSummary(film, result, std::nullopt, cpuSeconds, device, o.clamp > 0);
        return 0;
    }
    return withContext(global, [&](vk::Context& context) {
        wavefront::GpuRenderer renderer(context, scene, settings);
        std::fprintf(stderr, "%s\n", wavefront::describeMemory(renderer.scene(), renderer.tables()).c_str());
        std::fprintf(stderr, "%s\n", renderer.describe().c_str());
        double cpuSeconds = 0;
        const auto result = renderWithProgress(renderer, samples, film, o.timeBudget, cpuSeconds);
        writeOutputs(o, samples, result, context.info().name);
        double deviceMs = 0;
        for (const auto& [stage, ms] : result.stageMilliseconds) deviceMs += ms;
        printSummary(film, result, deviceMs, cpuSeconds, context.info().name, o.clamp > 0);
        if (o.timings) {
            for (const auto& [stage, ms] : result.stageMilliseconds)
                std::fprintf(stderr, "  %-15s %10.3f ms  %5.1f%%\n", stage.c_str(), ms, deviceMs > 0 ? 100 * ms / deviceMs : 0.0);
        }
        return 0;
    });
}

}  // namespace

void addRenderCommand(CLI::App& app, const GlobalOptions& global, Commands& commands) {
    auto o = std::make_shared<RenderCommandOptions>();
    auto* cmd = app.add_subcommand("render", "Render a scene with the GPU wavefront path tracer (or the CPU reference)");
    addRenderOptions(*cmd, *o);
    cmd->add_option("-o,-w,--output", o->output, "Output EXR (linear RGB float)")->capture_default_str();
    cmd->add_option("-s,--spp", o->spp, "Samples per pixel (default 16; with --time-budget, as many as it allows)");
    cmd->add_option("--samples", o->samples,
                    "FIRST:COUNT: render sample indices FIRST to FIRST + COUNT - 1 of every pixel (instead of -s), a "
                    "part for `vkpath merge`");
    cmd->add_option("--png", o->png, "Also write an sRGB PNG preview");
    cmd->add_option("--exposure", o->exposure, "PNG exposure in stops")->capture_default_str();
    cmd->add_option("--time-budget", o->timeBudget,
                    "Render whole waves until this many seconds are spent (up to -s samples if given); the EXR and "
                    "the summary give the spp reached");
    cmd->add_option("--aov", o->aovs, "Extra outputs beside the EXR: variance (of each pixel's mean)")
        ->check(CLI::IsMember({"variance"}));
    cmd->add_flag("--timings", o->timings, "Print the device time of each stage");
    cmd->callback([&global, &commands, o] { commands.run = [&global, o] { return runRender(global, *o); }; });
}

}  // namespace vkpath::app
