#include "wavefront/renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <future>
#include <map>
#include <stdexcept>
#include <utility>

#include "input_error.h"
#include "scene/camera.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/scene_arrays.h"
#include "shared/wavefront.h"
#include "vk/buffer.h"
#include "vk/check.h"
#include "vk/context.h"
#include "vk/kernel.h"
#include "vk/timestamps.h"
#include "wavefront/kernel_features.h"
#include "wavefront/path_buffers.h"
#include "wavefront/pipeline_set.h"
#include "wavefront/sample_schedule.h"
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
    // An adaptive pass's pixel list (shared/wavefront.h VKP_WF_PIXEL_LIST):
    // one uvec2 per pixel with adaptive sampling, else the placeholder.
    vk::Buffer pixelList;
    // The film in windows of consecutive pixels, each within one storage
    // binding and one dispatch (shared/wavefront.h WavePush.filmFirstPixel).
    uint32_t filmWindowPixels = 0;
    std::vector<vk::Buffer> film;
    // With two sample streams: the odd stream's sums, in the same windows;
    // else oddPlaceholder is bound (accumulate may write the binding, so it
    // shares no buffer with a binding read elsewhere).
    std::vector<vk::Buffer> filmOdd;
    vk::Buffer oddPlaceholder;
    // With the AOVs (RenderSettings::surfaceAovs): their sums, in the same
    // windows; else aovPlaceholder is bound (as oddPlaceholder, written by
    // accumulate). Not part of the film's state: a resumed render's AOVs are
    // its own samples'.
    std::vector<vk::Buffer> filmAov;
    vk::Buffer aovPlaceholder;
    PathBuffers paths;
    std::unique_ptr<PipelineSet> pipelines;

    // The buffers of the film's state (RenderState::film), in its order: the
    // windows in pixel order, then the odd stream's.
    std::vector<vk::Buffer*> filmState() {
        std::vector<vk::Buffer*> buffers;
        for (vk::Buffer& window : film) buffers.push_back(&window);
        for (vk::Buffer& window : filmOdd) buffers.push_back(&window);
        return buffers;
    }
    uint64_t filmBytes() {
        uint64_t bytes = 0;
        for (const vk::Buffer* buffer : filmState()) bytes += buffer->size();
        return bytes;
    }
    uint64_t aovBytes() const {
        uint64_t bytes = 0;
        for (const vk::Buffer& window : filmAov) bytes += window.size();
        return bytes;
    }
};

GpuRenderer::GpuRenderer(vk::Context& context, const scene::Scene& scene,
                         const RenderSettings& settings)
    : m_context(context),
      m_settings(settings),
      m_constructed(Clock::now()),
      m_tables(buildSceneTables(
          scene, {}, [&](const SceneTables& beforeBvh) { startPrewarm(beforeBvh, scene); })) {
    setUp();
}

GpuRenderer::GpuRenderer(vk::Context& context, SceneTables tables, const RenderSettings& settings)
    : m_context(context),
      m_settings(settings),
      m_constructed(Clock::now()),
      m_tables(std::move(tables)) {
    setUp();
}

PipelineSetup GpuRenderer::pipelineSetup(uint64_t features, bool byAddress,
                                         uint32_t lightSamples) const {
    const KernelForm form = m_settings.kernel.value_or(defaultKernelForm(m_context.info()));
    return PipelineSetup{
        .form = form,
        .shadowStage =
            form == KernelForm::Wavefront && shadowRaysPerVertex(features, lightSamples) > 0,
        .workgroupSize = m_settings.workgroupSize,
        .sceneSpecialization = {bvh::sceneAccessConstant(byAddress), featureConstants(features)[0],
                                featureConstants(features)[1]},
        .megakernelPathsPerInvocation = m_settings.megakernelPathsPerInvocation,
        .traversal = m_settings.traversal.value_or(defaultTraversal(m_context.info()))};
}

void GpuRenderer::startPrewarm(const SceneTables& beforeBvh, const scene::Scene& scene) {
    // A small scene's BVH is built before its pipelines would gain anything.
    const std::optional<uint64_t> traversalFeatures = bvh::predictedTraversalFeatures(scene);
    if (!traversalFeatures) return;
    const shared::SceneInfo info = renderSceneInfo(beforeBvh, m_settings);
    const uint64_t features = m_settings.specialize
                                  ? renderFeatures(beforeBvh, info) | *traversalFeatures
                                  : VKP_FEATURES_ALL;
    // Whether the scene will be read by address: as uploadScene decides,
    // with the BVH's arrays at their largest (a record of three texels per
    // interior node, fewer than the primitives; a primitive per triangle,
    // sphere and instance).
    uint64_t primitives = scene.spheres.size() + scene.instances.size();
    for (const scene::Mesh& mesh : scene.meshes) primitives += mesh.triangles.size();
    std::vector<vk::ArrayExtent> extents = {
        {"BVH node", primitives * VKP_BVH_RECORD_TEXELS * sizeof(glm::uvec4), primitives},
        {"BVH primitive", primitives * sizeof(shared::BvhPrimitive), primitives}};
#define VKP_ARRAY_EXTENT(index, name, Record, access, member) \
    VKP_SCENE_ARRAY_IF_SPANS_##access(                        \
        extents.push_back({#name, beforeBvh.member.size() * sizeof(beforeBvh.member[0]), 0});)
    VKP_SCENE_ARRAYS(VKP_ARRAY_EXTENT)
#undef VKP_ARRAY_EXTENT
    bool byAddress = false;
    try {
        byAddress = vk::chooseAddressAccess(extents, vk::bufferLimits(m_context.info()));
    } catch (const InputError&) {
        return;  // too large: uploadScene will say so
    }
    const PipelineSetup setup = pipelineSetup(features, byAddress, info.lightSamples);
    if (setup.traversal != bvh::Traversal::Compute) return;
    m_prewarmSetup = setup;
    m_prewarm = std::async(std::launch::async, [this, setup] {
        // A guess that fails costs nothing but the guess: the render builds
        // its pipelines itself, and reports what fails there.
        try {
            prewarmPipelines(m_context, setup);
        } catch (...) {
            m_prewarmSetup.reset();
        }
    });
}

void GpuRenderer::setUp() {
    vk::Context& context = m_context;
    const RenderSettings& settings = m_settings;
    // The context is this thread's again (prewarmPipelines submits to its queue).
    if (m_prewarm.valid()) m_prewarm.get();
    const shared::Camera camera =
        scene::makeGpuCamera(m_tables.camera, settings.width, settings.height);
    m_traversal = settings.traversal.value_or(defaultTraversal(context.info()));
    m_scene = uploadScene(context, m_tables, m_traversal);

    shared::SceneInfo& info = m_tables.info;
    info = renderSceneInfo(m_tables, settings);
    m_form = settings.kernel.value_or(defaultKernelForm(context.info()));
    m_features = settings.specialize ? renderFeatures(m_tables, info) : VKP_FEATURES_ALL;
    const PipelineSetup setup = pipelineSetup(m_features, m_scene.byAddress, info.lightSamples);
    m_prewarmed = m_prewarmSetup && *m_prewarmSetup == setup;

    auto r = std::make_unique<Resources>();
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    // Light samples traced per vertex: none where no stage could queue one.
    const uint32_t shadowSamples = shadowRaysPerVertex(m_features, info.lightSamples);
    r->shadowStage = setup.shadowStage;
    const PathExtras extras{settings.surfaceAovs, (m_features & VKP_FEATURE_DISPERSION) != 0};
    const uint64_t budget =
        pathStateBudget(settings, m_scene.bytes(), m_form, shadowSamples, extras);
    // The SceneInfo, then the guide spheres it counts (stages/lib/scene_access.glsl).
    std::vector<std::byte> sceneInfoBytes(sizeof(info) + info.guideSphereCount * sizeof(glm::vec4));
    std::memcpy(sceneInfoBytes.data(), &info, sizeof(info));
    if (info.guideSphereCount > 0)
        std::memcpy(sceneInfoBytes.data() + sizeof(info), m_tables.guideSpheres.data(),
                    info.guideSphereCount * sizeof(glm::vec4));
    r->sceneInfo = vk::Buffer::fromSpan(context, std::span(sceneInfoBytes), "sceneInfo");
    m_sceneMemory = describeMemory(m_scene, m_tables);
    // Before the pipelines and the path state take their memory.
    releaseUploaded(m_tables);
    r->camera = vk::Buffer::fromSpan(context, std::span(&camera, 1), "camera");
    r->counters =
        vk::Buffer(context, sizeof(shared::QueueCounters), vk::MemoryKind::DeviceLocal, "counters");
    r->filmWindowPixels = filmWindowPixels(settings, context.info());
    for (uint64_t first = 0; first < pixels; first += r->filmWindowPixels) {
        const uint64_t windowPixels = std::min<uint64_t>(r->filmWindowPixels, pixels - first);
        r->film.emplace_back(context, windowPixels * sizeof(shared::FilmPixel),
                             vk::MemoryKind::DeviceLocal, "film");
        if (info.sampleStreams == 2)
            r->filmOdd.emplace_back(context, windowPixels * sizeof(shared::FilmStreamPixel),
                                    vk::MemoryKind::DeviceLocal, "filmOdd");
        if (settings.surfaceAovs)
            r->filmAov.emplace_back(context, windowPixels * sizeof(shared::FilmAovPixel),
                                    vk::MemoryKind::DeviceLocal, "filmAov");
    }
    r->placeholder = vk::Buffer(context, 4, vk::MemoryKind::DeviceLocal, "placeholder");
    if (r->filmOdd.empty())
        r->oddPlaceholder = vk::Buffer(context, sizeof(shared::FilmStreamPixel),
                                       vk::MemoryKind::DeviceLocal, "film odd placeholder");
    if (r->filmAov.empty())
        r->aovPlaceholder = vk::Buffer(context, sizeof(shared::FilmAovPixel),
                                       vk::MemoryKind::DeviceLocal, "film AOV placeholder");
    if (settings.adaptive)
        r->pixelList = vk::Buffer(context, pixels * sizeof(glm::uvec2), vk::MemoryKind::DeviceLocal,
                                  "pixelList");
    r->paths = allocatePathBuffers(context, settings, m_form, shadowSamples, extras, budget);
    m_memory = {
        {"scene", m_scene.bytes()},
        {"path state", r->paths.bytes},
        {"film", r->filmBytes() + r->aovBytes() + (settings.adaptive ? r->pixelList.size() : 0)}};

    std::map<uint32_t, const vk::Buffer*> bindings = {
        {VKP_WF_SCENE_INFO, &r->sceneInfo},
        {VKP_WF_CAMERA, &r->camera},
        {VKP_WF_COUNTERS, &r->counters},
        {VKP_WF_FILM, &r->film.front()},
        {VKP_WF_PIXEL_LIST, settings.adaptive ? &r->pixelList : &r->placeholder},
        {VKP_WF_FILM_ODD, r->filmOdd.empty() ? &r->oddPlaceholder : &r->filmOdd.front()},
        {VKP_WF_FILM_AOV, r->filmAov.empty() ? &r->aovPlaceholder : &r->filmAov.front()},
    };
    for (const auto& [binding, buffer] : m_scene.bindings()) bindings[binding] = buffer;
    bindPathBuffers(r->paths, r->placeholder, bindings);

    const auto start = Clock::now();
    r->pipelines = std::make_unique<PipelineSet>(context, setup, bindings, r->film, r->filmOdd,
                                                 r->filmAov, r->counters);
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

// "specialised to <features>", and the feature profile whose build runs them.
static std::string specialisedTo(uint64_t features) {
    const char* profile = featureProfile(features);
    return fmt::format("specialised to {}{}", describeFeatures(features),
                       profile ? fmt::format(", from the {} profile's build", profile) : "");
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
        "kernels: {}, {} traversal, {} ({} pipelines in {:.0f} ms{}, ready {:.0f} ms after the "
        "scene was loaded); device memory {:.1f} MiB: {} ({} paths in flight)",
        kernelFormName(m_form), bvh::traversalName(m_traversal),
        m_settings.specialize ? specialisedTo(m_features)
                              : std::string("general (--no-specialize)"),
        m_pipelines, m_pipelineMilliseconds,
        m_prewarmed ? ", compiled while the BVH was built" : "", m_setupMilliseconds,
        total / (1024.0 * 1024.0), memory, pathsInFlight());
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
        for (vk::Buffer* buffer : r.filmState()) {
            buffer->upload(std::span(control.resume->film).subspan(offset, buffer->size()));
            offset += buffer->size();
        }
    } else {
        for (vk::Buffer* buffer : r.filmState()) buffer->clear();
    }
    for (vk::Buffer& window : r.filmAov) window.clear();
    r.counters.clear();
    result.priorSeconds = before.seconds;

    SampleSchedule schedule(s, samples, before, pixels);
    // The state now: the device's film and counters on top of what came before.
    auto state = [&](std::vector<std::byte> film, const shared::QueueCounters& counters,
                     double seconds) {
        const RunTally run{counters.nonFinite,
                           counters.fireflies,
                           counters.rejectedLightSamples,
                           {join64(counters.closestRays), join64(counters.shadowRays)},
                           result.waves,
                           seconds};
        RenderState now = continuedState(before, std::move(film), run);
        schedule.store(now);
        return now;
    };
    auto filmBytes = [&] {  // the film's state (Resources::filmState)
        std::vector<std::byte> film(r.filmBytes());
        size_t offset = 0;
        for (const vk::Buffer* buffer : r.filmState()) {
            buffer->download(std::span(film).subspan(offset, buffer->size()));
            offset += buffer->size();
        }
        return film;
    };

    // The film's per-pixel statistics (downloaded).
    auto statistics = [&] {
        const std::vector<std::byte> film = filmBytes();
        std::vector<PixelStatistics> stats(pixels);
        for (size_t i = 0; i < pixels; ++i) {
            shared::FilmPixel f;
            std::memcpy(&f, film.data() + i * sizeof(f), sizeof(f));
            for (int c = 0; c < 3; ++c) {
                // Kahan: the true sum is sum - compensation.
                const double sum = double(f.sum[c]) - double(f.sumCompensation[c]);
                const double sumSquares =
                    double(f.sumSquares[c]) - double(f.sumSquaresCompensation[c]);
                const PixelEstimate e = estimatePixel(sum, sumSquares, schedule.samplesOf(i));
                stats[i].mean[c] = e.mean;
                stats[i].varianceOfMean[c] = e.varianceOfMean;
            }
            if (!r.filmOdd.empty()) {
                shared::FilmStreamPixel odd;
                std::memcpy(&odd, film.data() + pixels * sizeof(f) + i * sizeof(odd), sizeof(odd));
                const glm::dvec3 oddSum = glm::dvec3(odd.sum) - glm::dvec3(odd.sumCompensation);
                stats[i].streamVarianceOfMean =
                    streamVarianceOfMean(stats[i].mean * double(schedule.samplesOf(i)), oddSum,
                                         samples.first, schedule.samplesOf(i));
            }
        }
        return stats;
    };

    const auto start = Clock::now();
    WholeSampleGate gate(control, s.timeBudgetSeconds);
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
    bool ended = false;
    while (!ended) {
        const std::optional<SamplePass> pass = schedule.next(statistics);
        if (!pass) break;
        // The pass's domain: the film's pixels, from the first sample index
        // they all have next, or its list of (pixel, first sample index).
        const bool listed = !pass->pixels.empty();
        const uint64_t domain = listed ? pass->pixels.size() : pixels;
        const uint32_t firstRound = listed ? 0 : samples.first + schedule.samplesOf(0);
        std::vector<uint32_t> windowEntries;
        if (listed) {
            std::vector<glm::uvec2> list(domain);
            for (size_t e = 0; e < domain; ++e)
                list[e] = {pass->pixels[e], samples.first + schedule.samplesOf(pass->pixels[e])};
            r.pixelList.upload(std::as_bytes(std::span(list)));
            for (size_t w = 0; w <= r.film.size(); ++w)
                windowEntries.push_back(
                    uint32_t(std::lower_bound(pass->pixels.begin(), pass->pixels.end(),
                                              std::min<uint64_t>(w * r.filmWindowPixels, pixels)) -
                             pass->pixels.begin()));
        }
        const uint64_t passPaths = domain * pass->rounds;
        uint64_t done = 0;  // paths of this pass
        while (done < passPaths && !ended) {
            // A wave holds whole rounds of every entry, or stays within one
            // round, so that each whole round ends a wave (stops, the time
            // budget and checkpoints come there) whatever the wave sizes.
            const uint64_t intoRound = done % domain;
            // (A short pixel list would otherwise put more rounds in a wave
            // than accumulate may loop over: MAX_ROUNDS_PER_WAVE.)
            const uint64_t fits = intoRound == 0 && wave >= domain
                                      ? std::min(wave / domain, MAX_ROUNDS_PER_WAVE) * domain
                                      : std::min<uint64_t>(wave, domain - intoRound);
            const uint32_t count = uint32_t(std::min<uint64_t>(fits, passPaths - done));
            const auto waveStart = Clock::now();
            const shared::WavePush first{.firstSample = uint32_t(firstRound + done / domain),
                                         .firstPixel = uint32_t(done % domain),
                                         .pathCount = count,
                                         .pixelListLength = listed ? uint32_t(domain) : 0u};
            m_context.submit([&](VkCommandBuffer cmd) {
                r.pipelines->recordWave(cmd, timestamps, first, bounces, r.counters, r.film,
                                        r.filmWindowPixels, windowEntries);
            });
            if (s.maxWaveMilliseconds)
                wave = nextWave(
                    count,
                    std::chrono::duration<double, std::milli>(Clock::now() - waveStart).count());
            for (const vk::TimedInterval& t : timestamps.results())
                result.stageMilliseconds[t.name] += t.milliseconds;
            const uint64_t roundsBefore = done / domain;
            done += count;
            result.paths += count;
            ++result.waves;
            for (uint64_t round = roundsBefore; round < done / domain; ++round)
                schedule.roundDone();
            const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
            const uint32_t samplesDone = schedule.wholeSamples();
            if (control.progress)
                control.progress(
                    {samplesDone, samples.count, seconds, schedule.lastEstimate(), result.paths});
            // Stops, the time budget and checkpoints: at whole rounds only.
            if (done % domain != 0) continue;
            if (gate.ends(samplesDone, samples.count, seconds, result.stopped)) {
                ended = true;
            } else if (gate.checkpointDue(samplesDone, samples.count)) {
                control.checkpoint(state(
                    filmBytes(), r.counters.download<shared::QueueCounters>().at(0), seconds));
                gate.checkpointed();
            }
            if (!ended)
                gate.previewIfDue(samplesDone, samples.count,
                                  [&] { return meanImage(statistics(), s.width, s.height); });
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (wave < r.paths.pathCount) result.cappedWavePaths = wave;

    const shared::QueueCounters counters = r.counters.download<shared::QueueCounters>().at(0);
    result.rays = {join64(counters.closestRays), join64(counters.shadowRays)};
    const RenderState end = state(filmBytes(), counters, result.seconds);
    result.takeTotals(end);
    result.reachedTarget = schedule.reachedTarget();
    if (control.checkpoint) control.checkpoint(end);
    takeImage(statistics(), s.width, s.height, result);
    if (!r.filmAov.empty()) {
        std::vector<shared::FilmAovPixel> sums;
        sums.reserve(pixels);
        for (const vk::Buffer& window : r.filmAov) {
            const std::vector<shared::FilmAovPixel> part = window.download<shared::FilmAovPixel>();
            sums.insert(sums.end(), part.begin(), part.end());
        }
        takeAovs(sums, s.width, s.height, result);
    }
    return result;
}

}  // namespace vkpath::wavefront
