// `vkpath render SCENE`: the wavefront path tracer (or, with --device cpu, the
// CPU reference running the same math), start to EXR.
#include "app/render_command.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/auto_choice.h"
#include "app/auto_search.h"
#include "app/checkpoint.h"
#include "app/commands.h"
#include "app/film_size.h"
#include "app/render_options.h"
#include "app/stop_signal.h"
#include "app/validators.h"
#include "image/denoiser.h"
#include "image/image.h"
#include "image/statistics.h"
#include "image/tev_client.h"
#include "input_error.h"
#include "reference/reference_renderer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "wavefront/renderer.h"
#include "wavefront/scene_footprint.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::app {
namespace {

// Before any rendering: `path`'s folder exists (made if need be) and a file
// can be created in it; throws InputError naming the flag otherwise.
void checkWritable(const std::string& flag, const std::filesystem::path& path) {
    const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec)
        throw InputError(fmt::format("{} {}: cannot create the folder {}: {}", flag, path.string(),
                                     folder.string(), ec.message()));
    if (std::filesystem::is_directory(path, ec))
        throw InputError(fmt::format("{} {}: is a folder", flag, path.string()));
    const auto probe = folder / fmt::format(".vkpath-write-test-{}", static_cast<long>(getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0)
        throw InputError(fmt::format("{} {}: cannot write in {}: {}", flag, path.string(),
                                     folder.string(), std::strerror(errno)));
    ::close(fd);
    ::unlink(probe.c_str());
}

// With a time budget the bar measures time, unless the sample count runs out
// first; with a target error, the estimate's way down to it (on log axes,
// from 1), when that is further.
void printProgress(const wavefront::RenderProgress& p, std::optional<double> timeBudget,
                   std::optional<double> targetError) {
    double fraction = p.samplesTotal ? double(p.samplesDone) / p.samplesTotal : 1.0;
    if (timeBudget && *timeBudget > 0)
        fraction = std::min(1.0, std::max(fraction, p.seconds / *timeBudget));
    if (targetError && p.estimatedRelMse && *targetError < 1)
        fraction = std::clamp(
            std::max(fraction, std::log(*p.estimatedRelMse) / std::log(*targetError)), 0.0, 1.0);
    const int width = 30;
    const int filled = int(fraction * width);
    const double mpaths = p.seconds > 0 ? double(p.paths) / p.seconds * 1e-6 : 0.0;
    const double eta = fraction > 0 ? p.seconds * (1 - fraction) / fraction : 0.0;
    const std::string error =
        p.estimatedRelMse ? fmt::format("  relMSE ~{:.2g}", *p.estimatedRelMse) : "";
    // No -s: no cap to show.
    const std::string samples = p.samplesTotal == UINT32_MAX
                                    ? fmt::format("{} spp", p.samplesDone)
                                    : fmt::format("{}/{} spp", p.samplesDone, p.samplesTotal);
    std::fprintf(stderr, "\r[%.*s%*s] %s  %.2f Mpaths/s%s  ETA %.1f s ", filled,
                 "##############################", width - filled, "", samples.c_str(), mpaths,
                 error.c_str(), eta);
}

// Either renderer, with a progress bar when stderr is a terminal (or
// `progress` instead, when given). Also measures the CPU time the whole
// process spent rendering (every thread, lavapipe's included), which on a
// shared machine varies far less than the wall clock.
template <typename Renderer>
wavefront::RenderResult renderWithProgress(
    Renderer& renderer, const wavefront::SampleRange& samples, std::optional<double> timeBudget,
    std::optional<double> targetError, wavefront::RenderControl control,
    const std::function<void(const wavefront::RenderProgress&)>& progress, double& cpuSeconds) {
    const bool terminal = !progress && isatty(STDERR_FILENO);
    const std::clock_t start = std::clock();
    control.progress = [&](const wavefront::RenderProgress& p) {
        if (progress) progress(p);
        if (terminal) printProgress(p, timeBudget, targetError);
    };
    wavefront::RenderResult result;
    try {
        result = renderer.render(samples, control);
    } catch (...) {
        if (terminal) std::fprintf(stderr, "\n");  // the error's line after the bar, not on it
        throw;
    }
    cpuSeconds = double(std::clock() - start) / CLOCKS_PER_SEC;
    if (terminal) std::fprintf(stderr, "\n");
    return result;
}

// "FIRST:COUNT" of --samples, within 32-bit sample indices; throws InputError.
wavefront::SampleRange parseSampleRange(const std::string& text) {
    const size_t colon = text.find(':');
    uint64_t first = 0, count = 0;
    auto number = [&](const std::string& digits, uint64_t& value) {
        if (digits.empty() || digits.size() > 10 ||
            digits.find_first_not_of("0123456789") != std::string::npos)
            return false;
        value = std::stoull(digits);
        return value <= UINT32_MAX;
    };
    if (colon == std::string::npos || !number(text.substr(0, colon), first) ||
        !number(text.substr(colon + 1), count) || count == 0)
        throw InputError(
            fmt::format("'{}' is not FIRST:COUNT, two whole numbers, COUNT at least 1", text));
    if (first + count > (uint64_t(1) << 32))
        throw InputError(fmt::format("'{}': sample indices beyond 2^32 - 1", text));
    return {uint32_t(first), uint32_t(count)};
}

// Samples per pixel: the least, the mean and the most.
struct SampleCounts {
    uint32_t least = 0;
    double mean = 0;
    uint32_t most = 0;
};
SampleCounts sampleCounts(const wavefront::RenderResult& result) {
    if (result.pixelSamples.empty())
        return {result.samplesPerPixel, double(result.samplesPerPixel), result.samplesPerPixel};
    SampleCounts c{UINT32_MAX, 0, 0};
    for (uint32_t n : result.pixelSamples) {
        c.least = std::min(c.least, n);
        c.most = std::max(c.most, n);
        c.mean += n;
    }
    c.mean /= double(result.pixelSamples.size());
    return c;
}

// The spp AOV: each pixel's sample count in every channel.
image::Image sampleCountImage(const wavefront::RenderResult& result) {
    image::Image counts(result.image.width, result.image.height);
    for (size_t i = 0; i < counts.pixels.size(); ++i) {
        const float n =
            float(result.pixelSamples.empty() ? result.samplesPerPixel : result.pixelSamples[i]);
        counts.pixels[i] = {n, n, n};
    }
    return counts;
}

// The EXR (with metadata), the AOVs beside it and the PNG preview.
void writeOutputs(const RenderCommandOptions& o, const RenderIdentity& identity,
                  const wavefront::SampleRange& samples, const wavefront::RenderResult& result,
                  const std::string& device, const std::optional<AutoChoice>& choice) {
    const std::filesystem::path output(o.output);
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
        {"vkpath:renderSeconds", fmt::format("{:.6f}", result.priorSeconds + result.seconds)},
        {"vkpath:nonFiniteSamples", std::to_string(result.nonFiniteSamples)},
        {"vkpath:fireflySamples", std::to_string(result.fireflySamples)},
        {"vkpath:rejectedLightSamples", std::to_string(result.rejectedLightSamples)},
        {"vkpath:clamp", o.clamp > 0 ? fmt::format("{}", o.clamp) : std::string("off")},
        {"vkpath:regularize",
         o.regularize > 0 ? fmt::format("{}", o.regularize) : std::string("off")},
        {"vkpath:microfacet", o.singleScattering ? "single-scattering" : "compensated"},
        {"vkpath:lightSampler", o.lightSampler},
        {"vkpath:guideSpheres",
         o.guideSpheres > 0 ? fmt::format("{}", o.guideSpheres) : std::string("off")},
        {"vkpath:scene", o.scene}};
    image::Metadata full = metadata;
    if (!o.variant.empty()) full.emplace_back("vkpath:variant", o.variant);
    if (const scene::Medium fog = fogOf(o); fog.present())
        full.emplace_back(
            "vkpath:fog",
            fmt::format("scattering {:.6g} {:.6g} {:.6g}, absorption {:.6g} {:.6g} {:.6g}, "
                        "anisotropy {:.6g} (per metre)",
                        fog.scattering.x, fog.scattering.y, fog.scattering.z, fog.absorption.x,
                        fog.absorption.y, fog.absorption.z, fog.anisotropy));
    if (!o.volume.empty()) {
        const glm::vec3 albedo = rgbOf(o.volumeAlbedo, "--volume-albedo");
        full.emplace_back("vkpath:volume",
                          fmt::format("{} grid '{}', density {:.6g}, albedo {:.6g} {:.6g} {:.6g}, "
                                      "anisotropy {:.6g}",
                                      o.volume, o.volumeGrid, o.volumeDensity, albedo.x, albedo.y,
                                      albedo.z, o.volumeAnisotropy));
    }
    if (result.estimatedRelMse)
        full.emplace_back("vkpath:estimatedRelMse", fmt::format("{:.6g}", *result.estimatedRelMse));
    if (o.targetError) {
        full.emplace_back("vkpath:targetError", fmt::format("{}", *o.targetError));
        full.emplace_back("vkpath:targetReached", result.reachedTarget ? "yes" : "no");
    }
    full.emplace_back("vkpath:adaptive",
                      o.adaptive ? fmt::format("warm-up {}", o.adaptiveWarmup) : "off");
    // Each pixel drew a prefix of this many indices from firstSample (merge).
    if (o.adaptive) full.emplace_back("vkpath:sampleRange", std::to_string(samples.count));
    const SampleCounts counts = sampleCounts(result);
    full.emplace_back("vkpath:sppMean", fmt::format("{:.6g}", counts.mean));
    full.emplace_back("vkpath:sppMax", std::to_string(counts.most));
    full.emplace_back("vkpath:auto", choice ? autoChoiceJson(*choice) : std::string("off"));
    image::writeExr(output, result.image, full);
    std::printf("%s\n", output.string().c_str());
    for (const std::string& aov : o.aovs) {
        const auto path = image::aovPath(output, aov);
        image::writeExr(path,
                        aov == "spp"      ? sampleCountImage(result)
                        : aov == "albedo" ? result.albedo
                        : aov == "normal" ? result.normal
                                          : result.varianceOfMean,
                        full);
        std::printf("%s\n", path.string().c_str());
    }
    if (!o.png.empty()) {
        image::writePng(o.png, result.image, o.exposure);
        std::printf("%s\n", o.png.c_str());
    }
    if (o.denoise) {
        // The raw image stays in -o; the denoised one beside it says what it is.
        // Its guides are the albedo and normal AOVs, which --denoise renders
        // whether or not --aov writes them (as Cycles' denoising data),
        // prefiltered: as good as or better than the guides as they are, or
        // none, on the suite (docs/TRADEOFFS.md, "Denoising").
        const image::DenoiseInputs inputs{&result.image, &result.albedo, &result.normal, true};
        const image::Denoised denoised = image::denoise(inputs);
        image::Metadata marked = full;
        marked.emplace_back("vkpath:denoised", image::denoisedMetadata(inputs));
        const auto path = image::aovPath(output, "denoised");
        image::writeExr(path, denoised.image, marked);
        std::fprintf(stderr, "denoised in %.3f s (%s)\n", denoised.seconds,
                     denoised.library.c_str());
        std::printf("%s\n", path.string().c_str());
    }
}

// `deviceMs`: the GPU's summed stage times (none on the CPU, whose waves are passes over the
// image).
void printSummary(const FilmSize& film, const wavefront::RenderResult& result,
                  std::optional<double> deviceMs, double cpuSeconds, const std::string& device,
                  bool clamped) {
    const double mpaths = result.seconds > 0 ? result.paths / result.seconds * 1e-6 : 0;
    const double mpathsPerCpuSecond = cpuSeconds > 0 ? result.paths / cpuSeconds * 1e-6 : 0;
    const double mrays = result.seconds > 0 ? result.rays.total() / result.seconds * 1e-6 : 0;
    const std::string deviceTime =
        deviceMs ? fmt::format(" (device {:.3f} s)", *deviceMs * 1e-3) : "";
    const SampleCounts counts = sampleCounts(result);
    const std::string spp = result.pixelSamples.empty()
                                ? fmt::format("{} spp", result.samplesPerPixel)
                                : fmt::format("{:.1f} spp on average ({} to {} per pixel)",
                                              counts.mean, counts.least, counts.most);
    std::fprintf(
        stderr,
        "rendered %ux%u at %s in %.3f s%s: %.3f Mpaths/s (%.3f per CPU second), %.3f Mrays/s "
        "(%llu closest-hit, %llu shadow), %u %s of %u paths, %llu NaN/Inf samples dropped, %llu "
        "fireflies%s, "
        "%llu light samples of pdf 0 skipped, on %s\n",
        film.width, film.height, spp.c_str(), result.seconds, deviceTime.c_str(), mpaths,
        mpathsPerCpuSecond, mrays, (unsigned long long)result.rays.closest,
        (unsigned long long)result.rays.shadow, result.waves, deviceMs ? "waves" : "passes",
        result.pathsInFlight, (unsigned long long)result.nonFiniteSamples,
        (unsigned long long)result.fireflySamples, clamped ? " (clamped)" : "",
        (unsigned long long)result.rejectedLightSamples, device.c_str());
}

// The checkpoint to resume (read before the knobs are settled: an --auto
// checkpoint holds its choice), matched against this render; throws
// InputError where it cannot continue it.
void checkResume(const RenderCommandOptions& o, const Checkpoint& checkpoint,
                 const RenderIdentity& identity, const wavefront::SampleRange& samples,
                 const FilmSize& film) {
    checkCheckpointMatches(o.resume, checkpoint, identity, samples);
    wavefront::checkResumable(
        checkpoint.state,
        o.device == "cpu" ? wavefront::CPU_FILM_FORMAT : wavefront::GPU_FILM_FORMAT, film.width,
        film.height, samples, o.resume);
}

// A resumed render's --auto choice: the checkpoint's, never a new one (the
// film's samples were drawn with it). nullopt without --resume or --auto;
// throws InputError where the flag and the checkpoint disagree.
std::optional<AutoChoice> resumedChoice(const RenderCommandOptions& o,
                                        const std::optional<Checkpoint>& checkpoint) {
    if (!checkpoint) return std::nullopt;
    if (!o.autoSettings && !checkpoint->autoChoice.empty())
        throw InputError(fmt::format(
            "{}: rendered with --auto ({}): resume it with --auto, which goes on with that choice",
            o.resume, describeAutoChoice(parseAutoChoice(checkpoint->autoChoice, o.resume))));
    if (!o.autoSettings) return std::nullopt;
    if (checkpoint->autoChoice.empty())
        throw InputError(fmt::format(
            "{}: rendered without --auto: resume it without --auto, with the same flags",
            o.resume));
    AutoChoice choice = parseAutoChoice(checkpoint->autoChoice, o.resume);
    choice.resumed = true;
    return choice;
}

// --auto's search on this device: pilots of the scene's tables, each its own
// renderer with the settings under test.
AutoChoice searchSettings(const RenderCommandOptions& o, const wavefront::SampleRange& samples,
                          const wavefront::SceneTables& tables, const PilotRenderer& pilots,
                          const vk::DeviceInfo* device) {
    AutoRequest request;
    request.base = renderSettings(o, samples.count);
    request.givenRouletteDepth = o.givenRouletteDepth;
    request.givenLightSamples = o.givenLightSamples;
    request.givenSampler = o.givenSampler;
    request.givenGuideSpheres = o.givenGuideSpheres;
    request.givenKernel = o.givenKernel;
    request.givenPathsInFlight = o.givenPathsInFlight;
    request.givenLightSampler = o.givenLightSampler;
    request.sceneHasLights = !tables.lights.empty();
    request.sceneHasLightTree = !tables.lightTree.nodes.empty();
    request.lightTreeByDefault = wavefront::usesLightTree(tables, request.base);
    request.sceneHasGuideSpheres = !tables.guideSpheres.empty();
    request.gpu = device != nullptr;
    if (device) {
        request.defaultForm = wavefront::defaultKernelForm(*device);
        request.defaultPathsInFlight = wavefront::defaultPathsInFlight(*device);
    }
    if (samples.count != UINT32_MAX) request.spp = samples.count;
    request.timeBudget = o.timeBudget;
    request.targetError = o.targetError;
    return chooseSettings(request, pilots);
}

// The render's options with the choice in place, its time budget less what
// the pilots spent of it.
void applyChoice(const AutoChoice& choice, RenderCommandOptions& o) {
    applyAutoChoice(choice, o);
    if (o.timeBudget && !choice.resumed)
        o.timeBudget = std::max(*o.timeBudget - choice.pilotSeconds, 1e-3);
    std::fprintf(stderr, "%s\n", describeAutoChoice(choice).c_str());
}

// A settings record (RenderIdentity::settings) whose "camera" is `camera`'s
// placement: renders from other cameras are other images.
std::string withCamera(const std::string& settings, const scene::Camera& camera) {
    nlohmann::ordered_json record = nlohmann::ordered_json::parse(settings);
    auto vec = [](glm::vec3 v) { return nlohmann::ordered_json{v.x, v.y, v.z}; };
    record["camera"] = {{"position", vec(camera.position)},
                        {"target", vec(camera.target)},
                        {"up", vec(camera.up)},
                        {"fov", camera.xfovDegrees},
                        {"aspect", camera.aspect}};
    return record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// The checkpoint a render that fails leaves to resume from: the last one it
// wrote, or the one it resumed from.
struct SavedCheckpoint {
    std::string path;
    uint32_t samplesDone = 0;
};

// Checkpoints while rendering (a failure there is a warning: the render goes
// on, the file keeps its last good state) and at the end (a failure is an
// error); each one written becomes `saved`.
// --display-server: the image so far at most this often (RenderControl::preview
// spaces them further where making one takes longer than 2% of the time).
constexpr double DISPLAY_EVERY_SECONDS = 0.25;
// How long the render waits at its end for the viewer to take the last image.
constexpr double DISPLAY_FINISH_SECONDS = 3.0;

wavefront::RenderControl renderControl(const RenderCommandOptions& o,
                                       const RenderIdentity& identity,
                                       const wavefront::SampleRange& samples,
                                       const std::optional<Checkpoint>& resume,
                                       const std::optional<AutoChoice>& choice,
                                       std::optional<SavedCheckpoint>& saved,
                                       image::TevClient* display) {
    wavefront::RenderControl control;
    control.stopRequested = [] { return StopOnSignal::requested() != 0; };
    if (display) {
        control.preview = [display](const image::Image& image) { display->show(image); };
        control.previewEverySeconds = DISPLAY_EVERY_SECONDS;
    }
    control.resume = resume ? &resume->state : nullptr;
    if (resume) saved = SavedCheckpoint{o.resume, resume->state.samplesDone};
    if (!o.checkpoint.empty()) {
        control.checkpointEverySeconds = o.checkpointEvery;
        const std::string autoChoice = choice ? autoChoiceJson(*choice) : std::string();
        control.checkpoint = [&o, identity, samples, autoChoice,
                              &saved](const wavefront::RenderState& state) {
            const Checkpoint checkpoint{identity, samples, state, autoChoice};
            const bool last = state.samplesDone == samples.count;
            try {
                writeCheckpoint(o.checkpoint, checkpoint);
                saved = SavedCheckpoint{o.checkpoint, state.samplesDone};
            } catch (const std::runtime_error& e) {
                if (last || StopOnSignal::requested()) throw;
                std::fprintf(stderr, "vkpath: warning: %s\n", e.what());
            }
        };
    }
    return control;
}

// Writes what a render made and says how it went; the exit code: 0, or
// 128 + the signal that stopped it.
int finishRender(const RenderCommandOptions& o, const RenderIdentity& identity,
                 const wavefront::SampleRange& samples, const FilmSize& film,
                 const wavefront::RenderResult& result, std::optional<double> deviceMs,
                 double cpuSeconds, const std::string& device,
                 const std::optional<AutoChoice>& choice, bool writeFiles) {
    const int signal = result.stopped ? StopOnSignal::requested() : 0;
    if (result.samplesPerPixel == 0) {
        std::fprintf(stderr, "vkpath: stopped before the first whole sample; no image written\n");
        return 128 + signal;
    }
    if (writeFiles) writeOutputs(o, identity, samples, result, device, choice);
    printSummary(film, result, deviceMs, cpuSeconds, device, o.clamp > 0);
    if (result.estimatedRelMse)
        std::fprintf(stderr, "estimated relMSE %.3g%s\n", *result.estimatedRelMse,
                     !o.targetError ? ""
                     : result.reachedTarget
                         ? fmt::format(" (target {} reached)", *o.targetError).c_str()
                         : fmt::format(" (target {} not reached)", *o.targetError).c_str());
    if (signal) {
        std::fprintf(stderr, "vkpath: stopped by signal %d at %u of %u spp%s\n", signal,
                     result.samplesPerPixel, samples.count,
                     o.checkpoint.empty()
                         ? ""
                         : fmt::format("; resume with --resume {}", o.checkpoint).c_str());
        return 128 + signal;
    }
    return 0;
}

}  // namespace

int runRender(const GlobalOptions& global, const RenderCommandOptions& flags,
              const RenderHooks& hooks) {
    RenderCommandOptions o = flags;  // --auto puts its choice in place of the knobs' values
    // The flags' values were checked as they were parsed (addRenderCommand).
    const FilmSize film = parseFilmSize(o.size);
    // A budget without -s renders until the budget is spent (sample indices
    // are 32-bit: at most 2^32 - 1 samples).
    wavefront::SampleRange samples{0, o.spp                             ? *o.spp
                                      : (o.timeBudget || o.targetError) ? UINT32_MAX
                                                                        : 16};
    if (!o.samples.empty()) samples = parseSampleRange(o.samples);
    if (o.adaptive && !o.timeBudget && !o.targetError)
        throw InputError(
            "--adaptive needs a stop: --target-error E or --time-budget S (-s N is then each "
            "pixel's most samples)");
    if (o.autoSettings && !o.samples.empty())
        throw InputError(
            "--auto with --samples: parts rendered apart would each choose their own settings "
            "and could not be merged; render one part with --auto and give the others the "
            "knobs it printed");
    renderSettings(o, samples.count);  // the flags that do not go together, before any work
    // Every output can be written before any time goes into rendering.
    if (hooks.writeFiles) {
        checkWritable("-o", o.output);
        for (const std::string& aov : o.aovs) checkWritable("--aov", image::aovPath(o.output, aov));
        if (!o.png.empty()) checkWritable("--png", o.png);
        if (o.denoise) checkWritable("--denoise", image::aovPath(o.output, "denoised"));
    }
    if (!o.checkpoint.empty()) checkWritable("--checkpoint", o.checkpoint);
    if (o.denoise) image::loadDenoiser();  // a missing library is one line before any rendering
    std::unique_ptr<image::TevClient> display;
    if (!o.displayServer.empty())
        display = std::make_unique<image::TevClient>(
            image::parseDisplayServer(o.displayServer, "--display-server"),
            std::filesystem::path(o.output).filename().string());
    // The final image, whatever ended the render.
    auto showFinal = [&](const wavefront::RenderResult& result) {
        if (!display || result.samplesPerPixel == 0) return;
        display->show(result.image);
        display->finish(DISPLAY_FINISH_SECONDS);
    };
    std::optional<scene::Scene> loaded;
    if (!hooks.scene) loaded = loadRenderScene(o);
    const scene::Scene& scene = hooks.scene ? *hooks.scene : *loaded;
    std::optional<Checkpoint> resume;
    if (!o.resume.empty()) resume = readCheckpoint(o.resume);
    std::optional<AutoChoice> choice = resumedChoice(o, resume);
    if (choice) applyChoice(*choice, o);
    // --auto: the scene's tables, built once for the pilots and the render
    // (for the GPU, once the device has admitted the scene).
    std::optional<wavefront::SceneTables> tables;
    if (hooks.tables) tables = *hooks.tables;
    if (!tables && (hooks.camera || (o.autoSettings && o.device == "cpu")))
        tables = wavefront::buildSceneTables(scene);
    if (hooks.camera) wavefront::placeCamera(*tables, *hooks.camera);

    // Once the knobs are settled: the identity, the resume and the controls.
    std::optional<SavedCheckpoint> saved;
    auto prepare = [&](RenderIdentity& identity, wavefront::RenderSettings& settings) {
        settings = renderSettings(o, samples.count);
        settings.timeBudgetSeconds = o.timeBudget;
        settings.surfaceAovs =
            o.denoise || std::any_of(o.aovs.begin(), o.aovs.end(), [](const std::string& aov) {
                return aov == "albedo" || aov == "normal";
            });
        identity =
            hooks.sceneHash.empty() ? renderIdentity(o, scene) : renderIdentity(o, hooks.sceneHash);
        if (hooks.camera) identity.settings = withCamera(identity.settings, *hooks.camera);
        if (resume) checkResume(o, *resume, identity, samples, film);
        wavefront::RenderControl control =
            renderControl(o, identity, samples, resume, choice, saved, display.get());
        if (hooks.stopRequested) control.stopRequested = hooks.stopRequested;
        return control;
    };
    std::optional<StopOnSignal> stopOnSignal;
    if (hooks.handleSignals) stopOnSignal.emplace();
    if (o.device == "cpu") {
        if (o.autoSettings && !choice) {
            choice = searchSettings(
                o, samples, *tables,
                [&](const wavefront::RenderSettings& s) {
                    const auto start = Clock::now();
                    const reference::ReferenceRenderer renderer(*tables, s);
                    const double setup = secondsSince(start);
                    const std::clock_t cpuStart = std::clock();
                    wavefront::RenderResult r = renderer.render();
                    const double cpu = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
                    return PilotRender{std::move(r.image), r.seconds, cpu, setup};
                },
                nullptr);
            applyChoice(*choice, o);
        }
        RenderIdentity identity;
        wavefront::RenderSettings settings;
        const wavefront::RenderControl control = prepare(identity, settings);
        const std::unique_ptr<reference::ReferenceRenderer> made =
            tables ? std::make_unique<reference::ReferenceRenderer>(std::move(*tables), settings)
                   : std::make_unique<reference::ReferenceRenderer>(scene, settings);
        const reference::ReferenceRenderer& renderer = *made;
        std::fprintf(stderr, "%s\n", renderer.describe().c_str());
        const std::string device = fmt::format("CPU reference ({} threads)", renderer.threads());
        double cpuSeconds = 0;
        const auto result = renderWithProgress(renderer, samples, o.timeBudget, o.targetError,
                                               control, hooks.progress, cpuSeconds);
        if (hooks.result) *hooks.result = result;
        showFinal(result);
        return finishRender(o, identity, samples, film, result, std::nullopt, cpuSeconds, device,
                            choice, hooks.writeFiles);
    }
    auto renderOnDevice = [&](vk::Context& context) {
        admitRenderOnDevice(o, scene, context.info());
        if (o.autoSettings && !tables) tables = wavefront::buildSceneTables(scene);
        if (o.autoSettings && !choice) {
            const bool cpuDevice = context.info().type == "cpu";
            choice = searchSettings(
                o, samples, *tables,
                [&](const wavefront::RenderSettings& s) {
                    const auto start = Clock::now();
                    wavefront::GpuRenderer renderer(context, *tables, s);
                    const double setup = secondsSince(start);
                    const std::clock_t cpuStart = std::clock();
                    wavefront::RenderResult r = renderer.render();
                    double cost = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
                    if (!cpuDevice) {  // a GPU: its own time
                        cost = 0;
                        for (const auto& [stage, ms] : r.stageMilliseconds) cost += ms * 1e-3;
                    }
                    return PilotRender{std::move(r.image), r.seconds, cost, setup};
                },
                &context.info());
            applyChoice(*choice, o);
        }
        RenderIdentity identity;
        wavefront::RenderSettings settings;
        const wavefront::RenderControl control = prepare(identity, settings);
        std::unique_ptr<wavefront::GpuRenderer> made =
            tables ? std::make_unique<wavefront::GpuRenderer>(context, std::move(*tables), settings)
                   : std::make_unique<wavefront::GpuRenderer>(context, scene, settings);
        wavefront::GpuRenderer& renderer = *made;
        std::fprintf(stderr, "%s\n", renderer.describeSceneMemory().c_str());
        std::fprintf(stderr, "%s\n", renderer.describe().c_str());
        double cpuSeconds = 0;
        // A device lost (or out of memory) mid-render ends it with one line
        // that says which checkpoint survives it.
        const auto result = [&] {
            try {
                return renderWithProgress(renderer, samples, o.timeBudget, o.targetError, control,
                                          hooks.progress, cpuSeconds);
            } catch (const vk::VulkanError& e) {
                if (!saved) throw;
                throw withLastCheckpoint(e, saved->path, saved->samplesDone);
            }
        }();
        if (result.cappedWavePaths)
            std::fprintf(
                stderr,
                "vkpath: waves capped at %g ms: %u paths per wave at the end (of %u in flight)\n",
                *settings.maxWaveMilliseconds, result.cappedWavePaths, result.pathsInFlight);
        showFinal(result);
        double deviceMs = 0;
        for (const auto& [stage, ms] : result.stageMilliseconds) deviceMs += ms;
        if (hooks.result) *hooks.result = result;
        const int code = finishRender(o, identity, samples, film, result, deviceMs, cpuSeconds,
                                      context.info().name, choice, hooks.writeFiles);
        if (o.timings) {
            for (const auto& [stage, ms] : result.stageMilliseconds)
                std::fprintf(stderr, "  %-15s %10.3f ms  %5.1f%%\n", stage.c_str(), ms,
                             deviceMs > 0 ? 100 * ms / deviceMs : 0.0);
        }
        return code;
    };
    if (hooks.context) return renderOnDevice(*hooks.context);
    return withContext(global, renderOnDevice);
}

void addRenderFlags(CLI::App& cmd, RenderCommandOptions& o) {
    addRenderOptions(cmd, o);
    cmd.add_option("-o,-w,--output", o.output, "Output EXR (linear RGB float)")
        ->capture_default_str();
    auto* spp =
        cmd.add_option("-s,--spp", o.spp,
                       "Samples per pixel (default 16; with --time-budget, as many as it allows)")
            ->check(CLI::Range(1u, UINT32_MAX));
    cmd.add_option("--samples", o.samples,
                   "FIRST:COUNT: render sample indices FIRST to FIRST + COUNT - 1 of every pixel "
                   "(instead of -s), a "
                   "part for `vkpath merge`")
        ->check(parsedBy("FIRST:COUNT", [](const std::string& text) { parseSampleRange(text); }))
        ->excludes(spp);
    cmd.add_option("--png", o.png, "Also write an sRGB PNG preview");
    cmd.add_option("--exposure", o.exposure, "PNG exposure in stops")
        ->check(finiteReal<float>())
        ->capture_default_str();
    cmd.add_option("--time-budget", o.timeBudget,
                   "Render whole waves until this many seconds are spent (up to -s samples if "
                   "given); the EXR and "
                   "the summary give the spp reached")
        ->check(realAbove<double>(0, false));
    cmd.add_option("--aov", o.aovs,
                   "Extra outputs beside the EXR (OUT.NAME.exr): variance (of each pixel's "
                   "mean), spp (each pixel's samples), albedo and normal (each pixel's mean "
                   "albedo and world-space shading normal of its first hit that is no mirror "
                   "or smooth glass, as Open Image Denoise defines them; 0 where the path left "
                   "the scene)")
        ->check(CLI::IsMember({"variance", "spp", "albedo", "normal"}))
        ->delimiter(',');
    cmd.add_flag("--timings", o.timings, "Print the device time of each stage");
    auto* checkpoint = cmd.add_option(
        "--checkpoint", o.checkpoint,
        "Keep the running film in this file (written atomically at whole samples, every "
        "--checkpoint-every seconds, on a stop and at the end), for --resume");
    cmd.add_option("--checkpoint-every", o.checkpointEvery,
                   "Seconds of rendering between checkpoints (0: after every whole sample)")
        ->check(realAtLeast<double>(0))
        ->capture_default_str()
        ->needs(checkpoint);
    cmd.add_flag("--denoise", o.denoise,
                 "Also write OUT.denoised.exr, denoised by Intel Open Image Denoise 2 (pip "
                 "install pyoidn; or VKPATH_OIDN_LIBRARY=path/to/libOpenImageDenoise.so.2), "
                 "guided by the albedo and normal AOVs (rendered for it, prefiltered); -o keeps "
                 "the raw render");
    cmd.add_option("--display-server", o.displayServer,
                   "HOST:PORT: show the render as it goes in the tev image viewer (start tev "
                   "first; it listens on 127.0.0.1:14158), updated at most every 0.25 s; the "
                   "render goes on if the viewer cannot be reached")
        ->type_name("HOST:PORT");
    cmd.add_option(
           "--resume", o.resume,
           "Go on from this checkpoint (same scene, settings and first sample; -s may be larger): "
           "the image equals the uninterrupted render's bit for bit")
        ->check(CLI::ExistingFile);
    cmd.add_flag(
        "--auto", o.autoSettings,
        "Choose --rr-depth, -l, --sampler, --light-sampler, --guide-spheres, --kernel and "
        "--paths-in-flight for "
        "this scene and device by short pilot renders (at most 5% of the render's budget: -s's "
        "time at the defaults, --time-budget or what --target-error implies); these knobs change "
        "the time to an error, never what the image converges to. Knobs given as flags are kept "
        "and not searched. The choice is printed and stored in the EXR (vkpath:auto) and the "
        "checkpoint, which --resume goes on with");
}

void noteGivenFlags(const CLI::App& cmd, RenderCommandOptions& o) {
    auto given = [&cmd](const char* name) { return cmd.get_option(name)->count() > 0; };
    o.givenRouletteDepth = given("--rr-depth");
    o.givenLightSamples = given("--light-samples");
    o.givenSampler = given("--sampler");
    o.givenGuideSpheres = given("--guide-spheres");
    o.givenKernel = given("--kernel");
    o.givenPathsInFlight = given("--paths-in-flight");
    o.givenLightSampler = given("--light-sampler");
}

void addRenderCommand(CLI::App& app, const GlobalOptions& global, Commands& commands) {
    auto o = std::make_shared<RenderCommandOptions>();
    auto* cmd = app.add_subcommand(
        "render", "Render a scene with the GPU wavefront path tracer (or the CPU reference)");
    addRenderFlags(*cmd, *o);
    cmd->callback([&global, &commands, o, cmd] {
        noteGivenFlags(*cmd, *o);
        commands.run = [&global, o] { return runRender(global, *o); };
    });
}

}  // namespace vkpath::app
