// What both integrators take and give: the GPU wavefront renderer
// (wavefront/renderer.h) and the CPU reference (reference/reference_renderer.h)
// read the same settings, fill the scene tables' SceneInfo the same way and
// turn per-pixel sums into the same mean and variance-of-mean images.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "image/image.h"
#include "shared/rng.h"
#include "shared/scene_data.h"
#include "shared/wavefront.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::wavefront {

// Where a path's random numbers come from (shared/rng.h): independent hashes,
// or Owen-scrambled Sobol' points stratified per pair of dimensions.
enum class SamplerKind : uint32_t {
    Independent = VKP_SAMPLER_INDEPENDENT,
    Sobol = VKP_SAMPLER_SOBOL
};

// The sampler named "independent" or "sobol" (--sampler, --sweep sampler=);
// nullopt for any other name.
std::optional<SamplerKind> parseSampler(const std::string& name);

// How a light sample chooses its light (shared/path/light_choice.h): by
// power alone, or through the light tree (shared/light_tree.h) by what each
// part of it may send the point; Auto: the tree where the scene has at least
// LIGHT_TREE_MIN_LIGHTS bounded lights.
enum class LightSampling { Auto, Power, Tree };
inline constexpr size_t LIGHT_TREE_MIN_LIGHTS = 8;

// "auto", "power" or "tree" (--light-sampler); nullopt for any other name.
std::optional<LightSampling> parseLightSampling(const std::string& name);
const char* lightSamplingName(LightSampling sampling);

// How the GPU runs the integrator's loop (shared/integrator.h): cut into
// stages with queues between them, or one invocation per whole path.
enum class KernelForm { Wavefront, Megakernel };

// "wavefront" or "megakernel" (--kernel); nullopt for any other name.
std::optional<KernelForm> parseKernelForm(const std::string& name);
const char* kernelFormName(KernelForm form);

struct RenderSettings {
    uint32_t width = 640;
    uint32_t height = 480;
    uint32_t samplesPerPixel = 16;
    uint32_t maxDepth = 8;      // pbrt-v4's meaning: 0 = emitters seen directly only
    uint32_t lightSamples = 1;  // light samples per diffuse vertex (-l)
    // Russian roulette from this bounce on. 5 (Mitsuba 3's default, counted
    // the same way) and the Sobol' sampler were chosen by time to error on the
    // bundled and shared scenes: docs/TRADEOFFS.md, "The defaults".
    uint32_t rouletteDepth = 5;
    uint32_t seed = 0;
    SamplerKind sampler = SamplerKind::Sobol;
    // > 0: clamp each path sample's largest component to this. Biased (it
    // removes energy), off by default; fireflies are counted either way.
    float clampRadiance = 0;
    // > 0: path regularisation (shared/bsdf.h regularizedMaterial): after a
    // path's first non-delta scattering, lobes of GGX alpha below this get it
    // (biased; 0: off)
    float regularize = 0;
    // Multiple-scattering compensation of the GGX lobes
    // (shaders/shared/microfacet_albedo.h); false: single scattering, as
    // Mitsuba 3 and pbrt-v4 render (render --single-scattering)
    bool microfacetCompensation = true;
    LightSampling lightSampling = LightSampling::Auto;
    // The share of a Lambertian vertex's BSDF samples drawn toward the smooth
    // specular spheres it sees (SceneTables::guideSpheres; shared/path_tracer.h
    // sampleGuidedDiffuse), in [0, 1); 0: off. Unbiased at any value; the
    // default was chosen by time to error (docs/TRADEOFFS.md).
    float guideFraction = 0.25f;
    std::optional<double> timeBudgetSeconds;  // stop after the wave that crosses it
    // Stop once the image's estimated relMSE (sample_schedule.h
    // estimatedRelMse) is at most this; unset: at the sample count.
    std::optional<double> targetError;
    // Adaptive sampling (sample_schedule.h): after adaptiveWarmup uniform
    // samples, more samples where the estimated error is largest;
    // samplesPerPixel is then each pixel's most.
    bool adaptive = false;
    uint32_t adaptiveWarmup = 16;
    // GPU: the form of the kernels; unset: the measured default for the
    // device's type (defaultKernelForm).
    std::optional<KernelForm> kernel;
    // GPU: how the kernels find hits (bvh::Traversal); unset: the measured
    // default for the device (defaultTraversal).
    std::optional<bvh::Traversal> traversal;
    // GPU: kernels specialised to the scene's features (shared/features.h);
    // false builds the general kernels (--no-specialize).
    bool specialize = true;
    uint32_t workgroupSize = 64;  // GPU: threads per workgroup of the stage kernels
    // GPU megakernel: paths each invocation traces one after another (path
    // regeneration); 1: one path per invocation, measured the faster on
    // lavapipe (docs/BENCHMARKS.md, "Kernel forms and specialisation").
    uint32_t megakernelPathsPerInvocation = 1;
    // GPU: upper bound on a wave's paths, also limited by device memory;
    // unset: by the device's type (defaultPathsInFlight).
    std::optional<uint32_t> maxPathsInFlight;
    // GPU: the most device memory the render's scene, film and path state may
    // take (bytes); the paths in flight get what the scene and film leave.
    std::optional<uint64_t> maxDeviceMemoryBytes;
    // GPU: waves sized to take at most this long (wall clock, ms; one that
    // takes longer makes the next ones smaller), for desktop GPUs whose
    // watchdog ends long submissions; unset: every wave holds all the paths
    // in flight. The image is the same either way.
    std::optional<double> maxWaveMilliseconds;
    // GPU: at most this many pixels per film window (0: what the device
    // allows, shared/wavefront.h WavePush.filmFirstPixel); smaller only to
    // test windows on small films.
    uint32_t filmWindowPixels = 0;
    uint32_t threads = 0;  // CPU reference: worker threads, 0 = every hardware thread
    // The albedo and normal AOVs (--aov albedo,normal; --denoise's guides):
    // each pixel's mean over its samples of what the path's first non-delta
    // hit shows (shared/integrator.h recordAov). Off: no AOV code in the
    // kernels, no AOV memory.
    bool surfaceAovs = false;
};
// The sample streams of a render (shared::SceneInfo::sampleStreams): 2 for a
// target error with the Sobol' sampler, whose error only two independent
// randomisations measure (sample_schedule.h streamVarianceOfMean), else 1.
uint32_t sampleStreams(const RenderSettings& settings);

// Samples [first, first + count) of every pixel. Random numbers are keyed by
// sample index, so renders of disjoint ranges are independent, and ranges
// rendered one after another, weighted by their counts, make one render of
// their union (up to float rounding): a render can be continued.
struct SampleRange {
    uint32_t first = 0;
    uint32_t count = 0;
};

// A pass of a render (wavefront/sample_schedule.h): `rounds` more samples of
// each of `pixels`, round after round, each pixel's next sample index first.
struct SamplePass {
    std::vector<uint32_t> pixels;  // ascending; empty: every pixel
    uint32_t rounds = 0;           // rounds left to render
};

struct RenderProgress {
    uint32_t samplesDone;  // per pixel (the least of any pixel's)
    uint32_t samplesTotal;
    double seconds;
    // The error estimate at the last pass end that measured it (a target-error
    // or adaptive render; sample_schedule.h), else unset.
    std::optional<double> estimatedRelMse = std::nullopt;
    uint64_t paths = 0;  // traced in this run so far
};

// Rays traced: one closest-hit ray per path segment, one shadow ray per light
// sample with a non-zero unoccluded contribution.
struct RayCounts {
    uint64_t closest = 0;
    uint64_t shadow = 0;
    uint64_t total() const { return closest + shadow; }
};

// A render's running state at a whole-sample boundary: the film's sums as
// the renderer keeps them, its counters and how far it got: enough to go on
// exactly where it stopped (app/checkpoint.h keeps it in a file). A pixel's
// samples are added in sample order whatever the waves were, so a render
// continued from this state equals the uninterrupted one bit for bit.
struct RenderState {
    // Whose sums `film` holds: the GPU's Kahan-compensated floats
    // (shared::FilmPixel) or the CPU reference's doubles.
    std::string filmFormat;
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t samplesDone = 0;  // whole samples per pixel, from the range's first
    // Adaptive sampling: each pixel's samples (empty while every pixel has
    // samplesDone), and the pass in progress, if any (SampleSchedule).
    std::vector<uint32_t> pixelSamples;
    std::optional<SamplePass> pass;
    std::vector<std::byte> film;
    uint64_t nonFiniteSamples = 0;
    uint64_t fireflySamples = 0;
    uint64_t rejectedLightSamples = 0;
    RayCounts rays;
    uint32_t waves = 0;
    double seconds = 0;  // rendering, over every run that made this state
};

// What a caller does to a render while it runs. Stops and checkpoints come at
// whole samples: where one sample of the film spans several waves (more
// pixels than paths in flight), the rest of it is rendered first.
struct RenderControl {
    std::function<void(const RenderProgress&)> progress;  // after every wave (pass)
    std::function<bool()> stopRequested;                  // true: stop at the next whole sample
    const RenderState* resume = nullptr;  // go on from this state (same film format and size)
    // Called with the state every `checkpointEverySeconds` of rendering and
    // once at the end (done, stopped or out of time budget).
    std::function<void(const RenderState&)> checkpoint;
    double checkpointEverySeconds = 0;
    // Called with the image so far (each pixel's mean) at whole samples, at
    // most every `previewEverySeconds` and never sooner after the last than
    // 49 times what that one took (making it: the film's download and its
    // statistics), so that previews cost at most 2% of the render.
    std::function<void(const image::Image&)> preview;
    double previewEverySeconds = 0;
};

// The film format names of RenderState.
inline constexpr const char* GPU_FILM_FORMAT = "gpu-f32-kahan";
inline constexpr const char* CPU_FILM_FORMAT = "cpu-f64";

// Throws InputError unless `state` can continue a render of `format` sums,
// `width` x `height` pixels and `samples` (`what` names the state's file).
void checkResumable(const RenderState& state, const char* format, uint32_t width, uint32_t height,
                    const SampleRange& samples, const std::string& what);

// What a render of `format` sums (`filmBytes` of them) starts from:
// control.resume, checked (checkResumable, the film's size) and copied
// without its film, or an empty state of that format and size.
RenderState resumedState(const RenderControl& control, const char* format, uint32_t width,
                         uint32_t height, const SampleRange& samples, size_t filmBytes);

// What one run of a renderer added to the state it started from.
struct RunTally {
    uint64_t nonFiniteSamples = 0;
    uint64_t fireflySamples = 0;
    uint64_t rejectedLightSamples = 0;
    RayCounts rays;
    uint32_t waves = 0;
    double seconds = 0;
};

// `before` with `film` (the sums now) and `run` added; the schedule's fields
// (how many samples, the pass) are SampleSchedule::store's.
RenderState continuedState(const RenderState& before, std::vector<std::byte> film,
                           const RunTally& run);

// The decisions both renderers take at each whole sample: end there (a stop
// request, or the time budget spent) or write a checkpoint first.
class WholeSampleGate {
  public:
    WholeSampleGate(const RenderControl& control, std::optional<double> timeBudgetSeconds);
    // True when the render ends at `done` of `total` samples, `seconds` into
    // this run; `stopped` is set when a stop request ended it early.
    bool ends(uint32_t done, uint32_t total, double seconds, bool& stopped) const;
    // True when a checkpoint is due (then the caller writes it and calls checkpointed()).
    bool checkpointDue(uint32_t done, uint32_t total) const;
    void checkpointed();
    // The same for RenderControl::preview: `make` gives the image, whose
    // making is timed to space the next.
    void previewIfDue(uint32_t done, uint32_t total, const std::function<image::Image()>& make);

  private:
    const RenderControl& m_control;
    std::optional<double> m_timeBudget;
    std::chrono::steady_clock::time_point m_lastCheckpoint;
    std::chrono::steady_clock::time_point m_nextPreview;
};

struct RenderResult {
    image::Image image;           // mean radiance per pixel
    image::Image varianceOfMean;  // per channel: sample variance / samples (the variance AOV)
    // RenderSettings::surfaceAovs: each pixel's mean albedo ([0, 1]) and
    // world-space normal over the samples of this run (a resumed state's
    // samples are not in them); empty otherwise.
    image::Image albedo;
    image::Image normal;
    uint32_t samplesPerPixel =
        0;                 // reached (less than asked when the time budget ran out or a stop came)
    bool stopped = false;  // RenderControl::stopRequested ended it early
    uint64_t nonFiniteSamples = 0;
    uint64_t fireflySamples =
        0;  // samples that alone add more than 1 to their pixel's mean (> spp)
    uint64_t rejectedLightSamples =
        0;               // light samples skipped because their pdf was 0 (shared/path_tracer.h)
    uint64_t paths = 0;  // traced in this run (not those of a resumed state)
    RayCounts rays;      // this run's
    uint32_t waves = 0;  // GPU: command buffers; CPU: passes over the image
    uint32_t pathsInFlight = 0;  // paths per wave (pass)
    // GPU, RenderSettings::maxWaveMilliseconds: the wave size the cap held
    // the waves to at the end; 0 when it let them hold every path in flight.
    uint32_t cappedWavePaths = 0;
    // Adaptive sampling: each pixel's samples (empty when every pixel has
    // samplesPerPixel, the least of them otherwise).
    std::vector<uint32_t> pixelSamples;
    std::optional<double> estimatedRelMse;  // at the end (sample_schedule.h)
    bool reachedTarget = false;             // RenderSettings::targetError ended it
    double seconds = 0;                     // wall clock of this run's waves
    double priorSeconds = 0;  // rendering before it, by the runs a resumed state came from
    std::map<std::string, double>
        stageMilliseconds;  // GPU: device time per stage (empty on the CPU)

    // The image's totals from the state the render ended in: spp and the counts.
    void takeTotals(const RenderState& end) {
        samplesPerPixel = end.samplesDone;
        pixelSamples = end.pixelSamples;
        nonFiniteSamples = end.nonFiniteSamples;
        fireflySamples = end.fireflySamples;
        rejectedLightSamples = end.rejectedLightSamples;
    }
};

// The scene tables' SceneInfo with the render's settings filled in (samples,
// depth, seed, sampler, film size); lightSamples is 0 when the scene has no light to
// sample, so emission then counts fully.
shared::SceneInfo renderSceneInfo(const SceneTables& tables, const RenderSettings& settings);

// Whether the render chooses its lights through the scene's light tree
// (settings.lightSampling, where the tables have one).
bool usesLightTree(const SceneTables& tables, const RenderSettings& settings);

// The albedo and normal images from per-pixel AOV sums (both renderers keep
// them as shared::FilmAovPixel, added in sample order): each sum over its
// pixel's count, 0 where a pixel has none.
void takeAovs(std::span<const shared::FilmAovPixel> sums, uint32_t width, uint32_t height,
              RenderResult& result);

// One pixel channel from `samples` path samples (NaN/Inf ones dropped count
// as zero): their mean and the variance of that mean (unbiased sample
// variance / samples; 0 with fewer than two samples).
struct PixelEstimate {
    double mean = 0;
    double varianceOfMean = 0;
};
PixelEstimate estimatePixel(double sum, double sumSquares, double samples);

}  // namespace vkpath::wavefront
