#include "wavefront/render_types.h"

#include <fmt/format.h>

#include <algorithm>

#include "input_error.h"

namespace vkpath::wavefront {

std::optional<SamplerKind> parseSampler(const std::string& name) {
    if (name == "independent") return SamplerKind::Independent;
    if (name == "sobol") return SamplerKind::Sobol;
    return std::nullopt;
}

std::optional<KernelForm> parseKernelForm(const std::string& name) {
    if (name == "wavefront") return KernelForm::Wavefront;
    if (name == "megakernel") return KernelForm::Megakernel;
    return std::nullopt;
}

std::optional<LightSampling> parseLightSampling(const std::string& name) {
    if (name == "auto") return LightSampling::Auto;
    if (name == "power") return LightSampling::Power;
    if (name == "tree") return LightSampling::Tree;
    return std::nullopt;
}

const char* lightSamplingName(LightSampling sampling) {
    return sampling == LightSampling::Power  ? "power"
           : sampling == LightSampling::Tree ? "tree"
                                             : "auto";
}

const char* kernelFormName(KernelForm form) {
    return form == KernelForm::Megakernel ? "megakernel" : "wavefront";
}

uint32_t sampleStreams(const RenderSettings& settings) {
    return settings.targetError && settings.sampler == SamplerKind::Sobol ? 2 : 1;
}

bool usesLightTree(const SceneTables& tables, const RenderSettings& settings) {
    if (tables.lightTree.nodes.empty() || settings.lightSampling == LightSampling::Power)
        return false;
    return settings.lightSampling == LightSampling::Tree ||
           tables.lightTree.trails.size() >= LIGHT_TREE_MIN_LIGHTS;
}

shared::SceneInfo renderSceneInfo(const SceneTables& tables, const RenderSettings& settings) {
    shared::SceneInfo info = tables.info;
    info.lightSamples = tables.lights.empty() ? 0 : settings.lightSamples;
    info.maxDepth = settings.maxDepth;
    info.rouletteDepth = settings.rouletteDepth;
    info.seed = settings.seed;
    info.samplerKind = uint32_t(settings.sampler);
    info.width = settings.width;
    info.height = settings.height;
    info.clampRadiance = settings.clampRadiance;
    info.regularizeAlpha = settings.regularize;
    info.guideSphereCount = settings.guideFraction > 0 ? uint32_t(tables.guideSpheres.size()) : 0u;
    info.guideFraction = info.guideSphereCount > 0 ? settings.guideFraction : 0.0f;
    // A firefly: one sample that alone adds more than 1 (display white) to its pixel's mean.
    info.fireflyThreshold = float(settings.samplesPerPixel);
    info.sampleStreams = sampleStreams(settings);
    info.aovs = settings.surfaceAovs ? 1u : 0u;
    info.microfacetCompensation = settings.microfacetCompensation && tables.roughLobes ? 1u : 0u;
    info.treeLights =
        usesLightTree(tables, settings) ? uint32_t(tables.lightTree.trails.size()) : 0u;
    return info;
}

void takeAovs(std::span<const shared::FilmAovPixel> sums, uint32_t width, uint32_t height,
              RenderResult& result) {
    result.albedo = image::Image(width, height);
    result.normal = image::Image(width, height);
    for (size_t i = 0; i < sums.size(); ++i) {
        const shared::FilmAovPixel& p = sums[i];
        const float weight = p.samples > 0 ? 1.0f / float(p.samples) : 0.0f;
        result.albedo.pixels[i] = p.albedo * weight;
        result.normal.pixels[i] = p.normal * weight;
    }
}

void checkResumable(const RenderState& state, const char* format, uint32_t width, uint32_t height,
                    const SampleRange& samples, const std::string& what) {
    auto writer = [](const std::string& f) {
        return f == GPU_FILM_FORMAT   ? "the GPU renderer"
               : f == CPU_FILM_FORMAT ? "the CPU reference (--device cpu)"
                                      : "?";
    };
    if (state.filmFormat != format)
        throw InputError(fmt::format("{}: written by {}; this render runs on {}", what,
                                     writer(state.filmFormat), writer(format)));
    if (state.width != width || state.height != height)
        throw InputError(fmt::format("{}: a {}x{} film; this render is {}x{}", what, state.width,
                                     state.height, width, height));
    if (!state.pixelSamples.empty() && state.pixelSamples.size() != uint64_t(width) * height)
        throw InputError(fmt::format("{}: sample counts of {} pixels for a {}x{} film", what,
                                     state.pixelSamples.size(), width, height));
    for (uint32_t n : state.pixelSamples)
        if (n > samples.count)
            throw InputError(fmt::format("{}: a pixel holds {} samples, more than the {} asked",
                                         what, n, samples.count));
    if (state.pass) {
        const std::vector<uint32_t>& list = state.pass->pixels;
        for (size_t i = 0; i < list.size(); ++i)
            if (list[i] >= uint64_t(width) * height || (i > 0 && list[i] <= list[i - 1]))
                throw InputError(fmt::format("{}: its pass lists pixel {} out of order or range",
                                             what, list[i]));
        if (!list.empty() && state.pixelSamples.empty())
            throw InputError(
                fmt::format("{}: a pass of listed pixels without their sample counts", what));
        for (uint32_t p : list)
            if (uint64_t(state.pixelSamples[p]) + state.pass->rounds > samples.count)
                throw InputError(fmt::format("{}: its pass takes pixel {} past {} samples", what, p,
                                             samples.count));
    }
    if (state.samplesDone > samples.count)
        throw InputError(fmt::format("{}: holds {} samples per pixel, more than the {} asked", what,
                                     state.samplesDone, samples.count));
}

RenderState resumedState(const RenderControl& control, const char* format, uint32_t width,
                         uint32_t height, const SampleRange& samples, size_t filmBytes) {
    RenderState before;
    if (control.resume) {
        checkResumable(*control.resume, format, width, height, samples, "the state to resume");
        if (control.resume->film.size() != filmBytes)
            throw InputError(fmt::format("the state to resume: {} bytes of film, expected {}",
                                         control.resume->film.size(), filmBytes));
        before.samplesDone = control.resume->samplesDone;
        before.pixelSamples = control.resume->pixelSamples;
        before.pass = control.resume->pass;
        before.nonFiniteSamples = control.resume->nonFiniteSamples;
        before.fireflySamples = control.resume->fireflySamples;
        before.rejectedLightSamples = control.resume->rejectedLightSamples;
        before.rays = control.resume->rays;
        before.waves = control.resume->waves;
        before.seconds = control.resume->seconds;
    }
    before.filmFormat = format;
    before.width = width;
    before.height = height;
    return before;
}

RenderState continuedState(const RenderState& before, std::vector<std::byte> film,
                           const RunTally& run) {
    RenderState now = before;
    now.film = std::move(film);
    now.nonFiniteSamples += run.nonFiniteSamples;
    now.fireflySamples += run.fireflySamples;
    now.rejectedLightSamples += run.rejectedLightSamples;
    now.rays.closest += run.rays.closest;
    now.rays.shadow += run.rays.shadow;
    now.waves += run.waves;
    now.seconds += run.seconds;
    return now;
}

WholeSampleGate::WholeSampleGate(const RenderControl& control,
                                 std::optional<double> timeBudgetSeconds)
    : m_control(control),
      m_timeBudget(timeBudgetSeconds),
      m_lastCheckpoint(std::chrono::steady_clock::now()),
      m_nextPreview(m_lastCheckpoint +
                    std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::duration<double>(control.previewEverySeconds))) {}

bool WholeSampleGate::ends(uint32_t done, uint32_t total, double seconds, bool& stopped) const {
    if (m_control.stopRequested && m_control.stopRequested()) {
        stopped = done < total;
        return true;
    }
    return m_timeBudget && seconds >= *m_timeBudget;
}

bool WholeSampleGate::checkpointDue(uint32_t done, uint32_t total) const {
    return m_control.checkpoint && done < total &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - m_lastCheckpoint)
                   .count() >= m_control.checkpointEverySeconds;
}

void WholeSampleGate::checkpointed() {
    m_lastCheckpoint = std::chrono::steady_clock::now();
}

void WholeSampleGate::previewIfDue(uint32_t done, uint32_t total,
                                   const std::function<image::Image()>& make) {
    using Clock = std::chrono::steady_clock;
    if (!m_control.preview || done >= total || Clock::now() < m_nextPreview) return;
    const auto begin = Clock::now();
    m_control.preview(make());
    const auto end = Clock::now();
    m_nextPreview = end + std::max<Clock::duration>(
                              std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(m_control.previewEverySeconds)),
                              49 * (end - begin));
}

PixelEstimate estimatePixel(double sum, double sumSquares, double samples) {
    PixelEstimate e;
    if (!(samples > 0)) return e;
    e.mean = sum / samples;
    const double variance =
        samples > 1 ? std::max(0.0, (sumSquares - samples * e.mean * e.mean) / (samples - 1)) : 0.0;
    e.varianceOfMean = variance / samples;
    return e;
}

}  // namespace vkpath::wavefront
