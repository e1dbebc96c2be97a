#include "wavefront/renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "scene/camera.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/wavefront.h"
#include "vk/buffer.h"
#include "vk/context.h"
#include "vk/kernel.h"
#include "vk/timestamps.h"

namespace vkpath::wavefront {
namespace {

using Clock = std::chrono::steady_clock;

// How many paths a wave holds: as many as memory allows up to the setting,
// rounded so that a wave holds whole samples of every pixel (or, for images
// larger than a wave, a whole sample is split into equal waves).
uint32_t pathsPerWave(const RenderSettings& s, const vk::DeviceInfo& device, uint64_t pixels) {
    const uint64_t bytesPerPath = sizeof(shared::Ray) + sizeof(shared::Hit) + 2 * sizeof(glm::vec3) +
                                  sizeof(shared::PathVertex) + 3 * sizeof(uint32_t) +
                                  s.lightSamples * (sizeof(shared::Ray) + sizeof(glm::vec3));
    uint64_t limit = s.maxPathsInFlight;
    limit = std::min<uint64_t>(limit, device.deviceLocalMemory / 4 / bytesPerPath);
    // The largest per-path array must fit one storage-buffer binding.
    limit = std::min<uint64_t>(limit, device.maxStorageBufferRange / (3 * sizeof(uint32_t)));
    limit = std::min<uint64_t>(limit, device.maxStorageBufferRange /
                                          (std::max<uint64_t>(1, s.lightSamples) * sizeof(shared::Ray)));
    limit = std::max<uint64_t>(limit, 1);
    // The accumulate stage loops over a pixel's samples in the wave, and
    // lavapipe cuts every shader loop at 65535 iterations.
    constexpr uint64_t MAX_SAMPLES_PER_WAVE = 65535;
    if (pixels <= limit)
        return uint32_t(pixels * std::min<uint64_t>({limit / pixels, s.samplesPerPixel, MAX_SAMPLES_PER_WAVE}));
    const uint64_t wavesPerSample = (pixels + limit - 1) / limit;
    return uint32_t((pixels + wavesPerSample - 1) / wavesPerSample);
}

}  // namespace

struct WavefrontRenderer::Resources {
    uint32_t pathCount = 0;  // paths in flight (the wave size)
    vk::Buffer sceneInfo, camera;
    vk::Buffer rays, hits, throughput, radiance, vertices, queues, counters, shadowRays, shadowRadiance, film;
    std::unique_ptr<vk::Kernel> generate, queueDispatch, intersect, shade, shadow, accumulate;
    vk::DescriptorSet generateSet, queueDispatchSet, intersectSet, shadeSet, shadowSet, accumulateSet;
};

WavefrontRenderer::WavefrontRenderer(vk::Context& context, const scene::Scene& scene, const RenderSettings& settings)
    : m_context(context), m_settings(settings), m_tables(buildSceneTables(scene)) {
    const shared::Camera camera = scene::makeGpuCamera(m_tables.camera, settings.width, settings.height);
    m_scene = uploadScene(context, m_tables);

    shared::SceneInfo& info = m_tables.info;
    info = renderSceneInfo(m_tables, settings);

    auto r = std::make_unique<Resources>();
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    const uint32_t w = r->pathCount = pathsPerWave(settings, context.info(), pixels);
    const uint32_t shadowSlots = std::max(1u, info.lightSamples) * w;
    r->sceneInfo = vk::Buffer::fromSpan(context, std::span(&info, 1), "sceneInfo");
    r->camera = vk::Buffer::fromSpan(context, std::span(&camera, 1), "camera");
    r->rays = vk::Buffer(context, uint64_t(w) * sizeof(shared::Ray), vk::MemoryKind::DeviceLocal, "rays");
    r->hits = vk::Buffer(context, uint64_t(w) * sizeof(shared::Hit), vk::MemoryKind::DeviceLocal, "hits");
    r->throughput = vk::Buffer(context, uint64_t(w) * sizeof(glm::vec3), vk::MemoryKind::DeviceLocal, "throughput");
    r->radiance = vk::Buffer(context, uint64_t(w) * sizeof(glm::vec3), vk::MemoryKind::DeviceLocal, "radiance");
    r->vertices = vk::Buffer(context, uint64_t(w) * sizeof(shared::PathVertex), vk::MemoryKind::DeviceLocal, "vertices");
    r->queues = vk::Buffer(context, uint64_t(w) * 3 * sizeof(uint32_t), vk::MemoryKind::DeviceLocal, "queues");
    r->counters = vk::Buffer(context, sizeof(shared::QueueCounters), vk::MemoryKind::DeviceLocal, "counters");
    r->shadowRays = vk::Buffer(context, uint64_t(shadowSlots) * sizeof(shared::Ray), vk::MemoryKind::DeviceLocal, "shadowRays");
    r->shadowRadiance = vk::Buffer(context, uint64_t(shadowSlots) * sizeof(glm::vec3), vk::MemoryKind::DeviceLocal, "shadowRadiance");
    r->film = vk::Buffer(context, pixels * sizeof(shared::FilmPixel), vk::MemoryKind::DeviceLocal, "film");

    const vk::KernelOptions options{.workgroupSize = settings.workgroupSize};
    vk::KernelOptions dispatchOptions{.workgroupSize = 1, .specialization = {{1, settings.workgroupSize}}};
    r->generate = std::make_unique<vk::Kernel>(context, "generate", options);
    r->queueDispatch = std::make_unique<vk::Kernel>(context, "queue_dispatch", dispatchOptions);
    // The kernels that read the scene, built for its access path (bound or by address).
    vk::KernelOptions sceneOptions = options;
    sceneOptions.specialization.push_back(bvh::sceneAccessConstant(m_scene.byAddress));
    r->intersect = std::make_unique<vk::Kernel>(context, "intersect", sceneOptions);
    r->shade = std::make_unique<vk::Kernel>(context, "shade", sceneOptions);
    r->shadow = std::make_unique<vk::Kernel>(context, "shadow", sceneOptions);
    r->accumulate = std::make_unique<vk::Kernel>(context, "accumulate", options);

    const GpuScene& g = m_scene;
    r->generateSet = r->generate->bind({{VKP_WF_SCENE_INFO, &r->sceneInfo}, {VKP_WF_CAMERA, &r->camera},
                                        {VKP_WF_RAYS, &r->rays}, {VKP_WF_THROUGHPUT, &r->throughput},
                                        {VKP_WF_RADIANCE, &r->radiance}, {VKP_WF_VERTEX, &r->vertices},
                                        {VKP_WF_QUEUES, &r->queues}, {VKP_WF_COUNTERS, &r->counters}});
    r->queueDispatchSet = r->queueDispatch->bind({{VKP_WF_COUNTERS, &r->counters}});
    r->intersectSet = r->intersect->bind({{VKP_WF_BVH_NODES, &g.bvh.nodeBinding()},
                                          {VKP_WF_BVH_PRIMITIVES, &g.bvh.primitiveBinding()},
                                          {VKP_WF_SCENE_ADDRESSES, &g.addresses},
                                          {VKP_WF_RAYS, &r->rays}, {VKP_WF_HITS, &r->hits},
                                          {VKP_WF_QUEUES, &r->queues}, {VKP_WF_COUNTERS, &r->counters}});
    r->shadeSet = r->shade->bind({{VKP_WF_SCENE_INFO, &r->sceneInfo}, {VKP_WF_BVH_NODES, &g.bvh.nodeBinding()},
                                  {VKP_WF_BVH_PRIMITIVES, &g.bvh.primitiveBinding()},
                                  {VKP_WF_SCENE_ADDRESSES, &g.addresses}, {VKP_WF_MATERIALS, &g.materials},
                                  {VKP_WF_LIGHTS, &g.binding(g.lights)}, {VKP_WF_LIGHT_ALIAS, &g.binding(g.lightAlias)},
                                  {VKP_WF_PRIMITIVE_LIGHT, &g.binding(g.primitiveLight)},
                                  {VKP_WF_ENV_ALIAS, &g.binding(g.envAlias)},
                                  {VKP_WF_ENV_RADIANCE, &g.binding(g.envRadiance)}, {VKP_WF_RAYS, &r->rays},
                                  {VKP_WF_HITS, &r->hits}, {VKP_WF_THROUGHPUT, &r->throughput},
                                  {VKP_WF_RADIANCE, &r->radiance}, {VKP_WF_VERTEX, &r->vertices},
                                  {VKP_WF_QUEUES, &r->queues}, {VKP_WF_COUNTERS, &r->counters},
                                  {VKP_WF_SHADOW_RAYS, &r->shadowRays}, {VKP_WF_SHADOW_RADIANCE, &r->shadowRadiance}});
    r->shadowSet = r->shadow->bind({{VKP_WF_SCENE_INFO, &r->sceneInfo}, {VKP_WF_BVH_NODES, &g.bvh.nodeBinding()},
                                    {VKP_WF_BVH_PRIMITIVES, &g.bvh.primitiveBinding()},
                                    {VKP_WF_SCENE_ADDRESSES, &g.addresses}, {VKP_WF_RADIANCE, &r->radiance},
                                    {VKP_WF_QUEUES, &r->queues}, {VKP_WF_COUNTERS, &r->counters},
                                    {VKP_WF_SHADOW_RAYS, &r->shadowRays}, {VKP_WF_SHADOW_RADIANCE, &r->shadowRadiance}});
    r->accumulateSet = r->accumulate->bind({{VKP_WF_SCENE_INFO, &r->sceneInfo}, {VKP_WF_RADIANCE, &r->radiance},
                                            {VKP_WF_COUNTERS, &r->counters}, {VKP_WF_FILM, &r->film}});
    m_resources = std::move(r);
}

WavefrontRenderer::~WavefrontRenderer() = default;

RenderResult WavefrontRenderer::render(const std::function<void(const RenderProgress&)>& progress) {
    return render(SampleRange{0, m_settings.samplesPerPixel}, progress);
}

RenderResult WavefrontRenderer::render(const SampleRange& samples,
                                       const std::function<void(const RenderProgress&)>& progress) {
    Resources& r = *m_resources;
    const RenderSettings& s = m_settings;
    const uint64_t pixels = uint64_t(s.width) * s.height;
    const uint64_t totalPaths = pixels * samples.count;
    // Global path indices (sampleIndex x pixels + pixel) are 32-bit in the kernels.
    const uint64_t firstPath = pixels * samples.first;
    if (firstPath + totalPaths > (uint64_t(1) << 32))
        throw std::out_of_range(fmt::format("samples [{}, {}) of {} pixels: path indices beyond 32 bits", samples.first,
                                            uint64_t(samples.first) + samples.count, pixels));
    const uint32_t bounces = s.maxDepth + 1;  // shading passes: hits at depth 0..maxDepth
    vk::TimestampPool timestamps(m_context, 2 + 5 * bounces);

    RenderResult result;
    result.pathsInFlight = r.pathCount;
    r.film.clear();
    r.counters.clear();
    const auto start = Clock::now();
    uint64_t done = 0;
    while (done < totalPaths) {
        const uint32_t count = uint32_t(std::min<uint64_t>(r.pathCount, totalPaths - done));
        auto pushFor = [&](uint32_t bounce, uint32_t mode) {
            shared::WavePush p{uint32_t(firstPath + done), count, bounce, mode};
            return p;
        };
        auto bytes = [](const shared::WavePush& p) { return std::as_bytes(std::span(&p, 1)); };
        m_context.submit([&](VkCommandBuffer cmd) {
            timestamps.reset(cmd);
            vk::computeBarrier(cmd);
            auto timed = [&](const char* name, auto&& work) {
                const uint32_t interval = timestamps.begin(cmd, name);
                work();
                timestamps.end(cmd, interval);
                vk::computeBarrier(cmd);
            };
            const auto p0 = pushFor(0, 0);
            timed("generate", [&] { r.generate->record(cmd, r.generateSet, count, bytes(p0)); });
            for (uint32_t bounce = 0; bounce < bounces; ++bounce) {
                const auto rays = pushFor(bounce, VKP_PREPARE_RAYS);
                const auto shadows = pushFor(bounce, VKP_PREPARE_SHADOWS);
                timed("queue_dispatch", [&] { r.queueDispatch->record(cmd, r.queueDispatchSet, 1, bytes(rays)); });
                const VkDeviceSize rayArgs = offsetof(shared::QueueCounters, rayDispatch);
                const VkDeviceSize shadowArgs = offsetof(shared::QueueCounters, shadowDispatch);
                timed("intersect", [&] { r.intersect->recordIndirect(cmd, r.intersectSet, r.counters, rayArgs, bytes(rays)); });
                timed("shade", [&] { r.shade->recordIndirect(cmd, r.shadeSet, r.counters, rayArgs, bytes(rays)); });
                timed("queue_dispatch", [&] { r.queueDispatch->record(cmd, r.queueDispatchSet, 1, bytes(shadows)); });
                timed("shadow", [&] { r.shadow->recordIndirect(cmd, r.shadowSet, r.counters, shadowArgs, bytes(shadows)); });
            }
            timed("accumulate", [&] { r.accumulate->record(cmd, r.accumulateSet, uint32_t(pixels), bytes(p0)); });
        });
        for (const vk::TimedInterval& t : timestamps.results()) result.stageMilliseconds[t.name] += t.milliseconds;
        done += count;
        ++result.waves;
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        const uint32_t samplesDone = uint32_t(done / pixels);
        if (progress) progress({samplesDone, samples.count, seconds});
        // Stop on a whole sample once the budget is spent.
        if (s.timeBudgetSeconds && seconds >= *s.timeBudgetSeconds && done % pixels == 0) break;
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.paths = done;
    result.samplesPerPixel = uint32_t(done / pixels);

    const auto counters = r.counters.download<shared::QueueCounters>();
    result.nonFiniteSamples = counters.at(0).nonFinite;
    result.fireflySamples = counters.at(0).fireflies;
    result.rejectedLightSamples = counters.at(0).rejectedLightSamples;
    auto join64 = [](glm::uvec2 lowHigh) { return uint64_t(lowHigh.x) | uint64_t(lowHigh.y) << 32; };
    result.rays = {join64(counters.at(0).closestRays), join64(counters.at(0).shadowRays)};
    const auto film = r.film.download<shared::FilmPixel>();
    result.image = image::Image(s.width, s.height);
    result.varianceOfMean = image::Image(s.width, s.height);
    const double n = result.samplesPerPixel;
    for (size_t i = 0; i < film.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            // Kahan: the true sum is sum - compensation.
            const double sum = double(film[i].sum[c]) - double(film[i].sumCompensation[c]);
            const double sumSquares = double(film[i].sumSquares[c]) - double(film[i].sumSquaresCompensation[c]);
            const PixelEstimate e = estimatePixel(sum, sumSquares, n);
            result.image.pixels[i][c] = float(e.mean);
            result.varianceOfMean.pixels[i][c] = float(e.varianceOfMean);
        }
    }
    return result;
}

}  // namespace vkpath::wavefront
