#include "wavefront/renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>

#include "input_error.h"
#include "scene/camera.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/wavefront.h"
#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/kernel.h"
#include "vk/timestamps.h"
#include "wavefront/kernel_features.h"
#include "wavefront/path_buffers.h"
#include "wavefront/pipeline_set.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::wavefront {
namespace {

using Clock = std::chrono::steady_clock;

uint64_t join64(glm::uvec2 lowHigh) {
    return uint64_t(lowHigh.x) | uint64_t(lowHigh.y) << 32;
}

}  // namespace

struct GpuRenderer::Resources {
    bool shadowStage = false;
    vk::Buffer sceneInfo, camera, counters, placeholder;
    // The film in windows of consecutive pixels, each within one storage
    // binding and one dispatch (shared/wavefront.h WavePush.filmFirstPixel).
    uint32_t filmWindowPixels = 0;
    std::vector<vk::Buffer> film;
    PathBuffers paths;
    std::unique_ptr<PipelineSet> pipelines;

    uint64_t filmBytes() const {
        uint64_t bytes = 0;
        for (const vk::Buffer& window : film) bytes += window.size();
        return bytes;
    }
};

GpuRenderer::GpuRenderer(vk::Context& context, const scene::Scene& scene,
                         const RenderSettings& settings)
    : m_context(context),
      m_settings(settings),
      m_constructed(Clock::now()),
      m_tables(buildSceneTables(scene)) {
    const shared::Camera camera =
        scene::makeGpuCamera(m_tables.camera, settings.width, settings.height);
    m_scene = uploadScene(context, m_tables);

    shared::SceneInfo& info = m_tables.info;
    info = renderSceneInfo(m_tables, settings);
    m_form = settings.kernel.value_or(defaultKernelForm(context.info()));
    m_features = settings.specialize ? renderFeatures(m_tables, info) : VKP_FEATURES_ALL;

    auto r = std::make_unique<Resources>();
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    // Light samples traced per vertex: none where no stage could queue one.
    const uint32_t shadowSamples = shadowRaysPerVertex(m_features, info.lightSamples);
    r->shadowStage = m_form == KernelForm::Wavefront && shadowSamples > 0;
    const uint64_t budget = pathStateBudget(settings, m_scene.bytes(), m_form, shadowSamples);
    // The SceneInfo, then the guide spheres it counts (stages/lib/scene_access.glsl).
    std::vector<std::byte> sceneInfoBytes(sizeof(info) + info.guideSphereCount * sizeof(glm::vec4));
    std::memcpy(sceneInfoBytes.data(), &info, sizeof(info));
    if (info.guideSphereCount > 0)
        std::memcpy(sceneInfoBytes.data() + sizeof(info), m_tables.guideSpheres.data(),
                    info.guideSphereCount * sizeof(glm::vec4));
    r->sceneInfo = vk::Buffer::fromSpan(context, std::span(sceneInfoBytes), "sceneInfo");
    r->camera = vk::Buffer::fromSpan(context, std::span(&camera, 1), "camera");
    r->counters =
        vk::Buffer(context, sizeof(shared::QueueCounters), vk::MemoryKind::DeviceLocal, "counters");
    r->filmWindowPixels = filmWindowPixels(settings, context.info());
    for (uint64_t first = 0; first < pixels; first += r->filmWindowPixels) {
        const uint64_t windowPixels = std::min<uint64_t>(r->filmWindowPixels, pixels - first);
        r->film.emplace_back(context, windowPixels * sizeof(shared::FilmPixel),
                             vk::MemoryKind::DeviceLocal, "film");
    }
    r->placeholder = vk::Buffer(context, 4, vk::MemoryKind::DeviceLocal, "placeholder");
    r->paths = allocatePathBuffers(context, settings, m_form, shadowSamples, budget);
    m_memory = {
        {"scene", m_scene.bytes()}, {"path state", r->paths.bytes}, {"film", r->filmBytes()}};

    std::map<uint32_t, const vk::Buffer*> bindings = {
        {VKP_WF_SCENE_INFO, &r->sceneInfo},
        {VKP_WF_CAMERA, &r->camera},
        {VKP_WF_COUNTERS, &r->counters},
        {VKP_WF_FILM, &r->film.front()},
    };
    for (const auto& [binding, buffer] : m_scene.bindings()) bindings[binding] = buffer;
    bindPathBuffers(r->paths, r->placeholder, bindings);

    const auto start = Clock::now();
    PipelineSetup setup{.form = m_form,
                        .shadowStage = r->shadowStage,
                        .workgroupSize = settings.workgroupSize,
                        .sceneSpecialization = {bvh::sceneAccessConstant(m_scene.byAddress),
                                                {VKP_SPEC_FEATURES, m_features}},
                        .megakernelPathsPerInvocation = settings.megakernelPathsPerInvocation};
    r->pipelines = std::make_unique<PipelineSet>(context, setup, bindings, r->film, r->counters);
    m_pipelines = r->pipelines->count();
    m_pipelineMilliseconds =
        std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    m_setupMilliseconds =
        std::chrono::duration<double, std::milli>(Clock::now() - m_constructed).count();
    m_resources = std::move(r);
}

GpuRenderer::~GpuRenderer() = default;

uint32_t GpuRenderer::pathsInFlight() const {
    return m_resources->paths.pathCount;
}

std::string GpuRenderer::describe() const {
    std::string memory;
    uint64_t total = 0;
    for (const MemoryGroup& group : m_memory) {
        memory += fmt::format("{}{} {:.1f} MiB", memory.empty() ? "" : ", ", group.name,
                              group.bytes / (1024.0 * 1024.0));
        total += group.bytes;
    }
    return fmt::format(
        "kernels: {}, {} ({} pipelines in {:.0f} ms, ready {:.0f} ms after the scene was loaded); "
        "device memory {:.1f} "
        "MiB: {} ({} paths in flight)",
        kernelFormName(m_form),
        m_settings.specialize ? "specialised to " + describeFeatures(m_features)
                              : std::string("general (--no-specialize)"),
        m_pipelines, m_pipelineMilliseconds, m_setupMilliseconds, total / (1024.0 * 1024.0), memory,
        pathsInFlight());
}

RenderResult GpuRenderer::render(const std::function<void(const RenderProgress&)>& progress) {
    return render(SampleRange{0, m_settings.samplesPerPixel}, progress);
}

RenderResult GpuRenderer::render(const SampleRange& samples,
                                 const std::function<void(const RenderProgress&)>& progress) {
    return render(samples, RenderControl{.progress = progress});
}

RenderResult GpuRenderer::render(const SampleRange& samples, const RenderControl& control) {
    Resources& r = *m_resources;
    const RenderSettings& s = m_settings;
    const uint64_t pixels = uint64_t(s.width) * s.height;
    const uint64_t totalPaths = pixels * samples.count;
    // Sample indices are 32-bit (pixels and samples are separate: shared/wavefront.h WavePush).
    if (uint64_t(samples.first) + samples.count > (uint64_t(1) << 32))
        throw std::out_of_range(fmt::format("samples [{}, {}): sample indices beyond 32 bits",
                                            samples.first,
                                            uint64_t(samples.first) + samples.count));
    const uint32_t bounces = s.maxDepth + 1;  // shading passes: hits at depth 0..maxDepth
    vk::TimestampPool timestamps(m_context, 3 + 5 * bounces);

    RenderResult result;
    result.pathsInFlight = r.paths.pathCount;
    const RenderState before =
        resumedState(control, GPU_FILM_FORMAT, s.width, s.height, samples, r.filmBytes());
    if (control.resume) {  // its film goes to the device
        size_t offset = 0;
        for (vk::Buffer& window : r.film) {
            window.upload(std::span(control.resume->film).subspan(offset, window.size()));
            offset += window.size();
        }
    } else {
        for (vk::Buffer& window : r.film) window.clear();
    }
    r.counters.clear();
    result.priorSeconds = before.seconds;

    // The state now: the device's film and counters on top of what came before.
    auto state = [&](std::vector<std::byte> film, const shared::QueueCounters& counters,
                     uint64_t done, double seconds) {
        const RunTally run{counters.nonFinite,
                           counters.fireflies,
                           counters.rejectedLightSamples,
                           {join64(counters.closestRays), join64(counters.shadowRays)},
                           result.waves,
                           seconds};
        return continuedState(before, uint32_t(done / pixels), std::move(film), run);
    };
    auto filmBytes = [&] {  // the windows, one after another: the film in pixel order
        std::vector<std::byte> film(r.filmBytes());
        size_t offset = 0;
        for (const vk::Buffer& window : r.film) {
            window.download(std::span(film).subspan(offset, window.size()));
            offset += window.size();
        }
        return film;
    };

    const auto start = Clock::now();
    WholeSampleGate gate(control, s.timeBudgetSeconds);
    uint64_t done = uint64_t(before.samplesDone) * pixels;
    // maxWaveMilliseconds: the next wave's size from the paths per
    // millisecond the last one managed, aimed at 3/4 of the cap (room for
    // waves that vary). Over the cap the waves shrink in proportion, never
    // below one workgroup's worth; under half of it they grow, up to the
    // paths in flight. The first is one workgroup's worth: a whole one might
    // already run over (and a watchdog end it).
    const uint32_t fewest = std::min(s.workgroupSize, r.paths.pathCount);
    uint32_t wave = s.maxWaveMilliseconds
                        ? fewest
                        : r.paths.pathCount;  // the most paths the next wave may hold
    auto nextWave = [&](uint32_t count, double milliseconds) {
        const double cap = *s.maxWaveMilliseconds;
        const double aimed = count * (0.75 * cap / std::max(milliseconds, 1e-3));
        if (milliseconds > cap) return uint32_t(std::clamp<double>(aimed, fewest, wave));
        if (milliseconds < cap / 2)
            return uint32_t(std::clamp<double>(aimed, wave, r.paths.pathCount));
        return wave;
    };
    while (done < totalPaths) {
        // A wave holds whole samples of every pixel, or stays within one
        // sample, so that each whole sample ends a wave (stops, the time
        // budget and checkpoints come there) whatever the wave sizes.
        const uint64_t intoSample = done % pixels;
        const uint64_t fits = intoSample == 0 && wave >= pixels
                                  ? wave / pixels * pixels
                                  : std::min<uint64_t>(wave, pixels - intoSample);
        const uint32_t count = uint32_t(std::min<uint64_t>(fits, totalPaths - done));
        const auto waveStart = Clock::now();
        const shared::WavePush first{uint32_t(samples.first + done / pixels),
                                     uint32_t(done % pixels), count};
        m_context.submit([&](VkCommandBuffer cmd) {
            r.pipelines->recordWave(cmd, timestamps, first, bounces, r.counters, r.film,
                                    r.filmWindowPixels);
        });
        if (s.maxWaveMilliseconds)
            wave = nextWave(
                count, std::chrono::duration<double, std::milli>(Clock::now() - waveStart).count());
        for (const vk::TimedInterval& t : timestamps.results())
            result.stageMilliseconds[t.name] += t.milliseconds;
        done += count;
        ++result.waves;
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        const uint32_t samplesDone = uint32_t(done / pixels);
        if (control.progress) control.progress({samplesDone, samples.count, seconds});
        // Stops, the time budget and checkpoints: at whole samples only.
        if (done % pixels != 0) continue;
        if (gate.ends(samplesDone, samples.count, seconds, result.stopped)) break;
        if (gate.checkpointDue(samplesDone, samples.count)) {
            control.checkpoint(state(
                filmBytes(), r.counters.download<shared::QueueCounters>().at(0), done, seconds));
            gate.checkpointed();
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.paths = done - uint64_t(before.samplesDone) * pixels;
    if (wave < r.paths.pathCount) result.cappedWavePaths = wave;

    const shared::QueueCounters counters = r.counters.download<shared::QueueCounters>().at(0);
    result.rays = {join64(counters.closestRays), join64(counters.shadowRays)};
    const RenderState end = state(filmBytes(), counters, done, result.seconds);
    result.takeTotals(end);
    if (control.checkpoint) control.checkpoint(end);
    result.image = image::Image(s.width, s.height);
    result.varianceOfMean = image::Image(s.width, s.height);
    const double n = result.samplesPerPixel;
    for (size_t i = 0; i < pixels; ++i) {
        shared::FilmPixel f;  // read in place: a copy of a large film would double its host memory
        std::memcpy(&f, end.film.data() + i * sizeof(f), sizeof(f));
        for (int c = 0; c < 3; ++c) {
            // Kahan: the true sum is sum - compensation.
            const double sum = double(f.sum[c]) - double(f.sumCompensation[c]);
            const double sumSquares = double(f.sumSquares[c]) - double(f.sumSquaresCompensation[c]);
            const PixelEstimate e = estimatePixel(sum, sumSquares, n);
            result.image.pixels[i][c] = float(e.mean);
            result.varianceOfMean.pixels[i][c] = float(e.varianceOfMean);
        }
    }
    return result;
}

}  // namespace vkpath::wavefront
