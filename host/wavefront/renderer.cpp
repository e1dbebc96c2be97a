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

namespace vkpath::wavefront {
namespace {

using Clock = std::chrono::steady_clock;

uint64_t join64(glm::uvec2 lowHigh) { return uint64_t(lowHigh.x) | uint64_t(lowHigh.y) << 32; }

// The per-path buffers of a wave, one row each: this table alone decides
// their sizes (and so how many paths a wave holds), allocates them and binds
// them (stages/lib/path_buffers.glsl and queues.glsl declare the same).
struct PathBufferRow {
    uint32_t binding;
    const char* name;
    uint64_t bytes;       // per path, or per light sample of a path
    bool perLightSample;  // holds one element per traced light sample
    bool megakernel;      // the megakernel uses it too (else only the wavefront stages)
};

constexpr PathBufferRow PATH_BUFFERS[] = {
    {VKP_WF_RAYS, "rays", sizeof(shared::Ray), false, false},
    {VKP_WF_HITS, "hits", sizeof(shared::Hit), false, false},
    {VKP_WF_THROUGHPUT, "throughput", sizeof(glm::vec3), false, false},
    {VKP_WF_RADIANCE, "radiance", sizeof(glm::vec3), false, true},
    {VKP_WF_VERTEX, "vertices", sizeof(shared::PathVertex), false, false},
    {VKP_WF_QUEUES, "queues", 3 * sizeof(uint32_t), false, false},  // stages/lib/queues.glsl
    {VKP_WF_SHADOW_RAYS, "shadowRays", sizeof(shared::Ray), true, false},
    {VKP_WF_SHADOW_RADIANCE, "shadowRadiance", sizeof(glm::vec3), true, false},
};

// Bytes per path of `row` in a render of this form that traces `shadowSamples`
// light samples per vertex; 0 when the render does not use it (a
// placeholder is bound to it).
uint64_t bytesPerPath(const PathBufferRow& row, KernelForm form, uint32_t shadowSamples) {
    if (form == KernelForm::Megakernel && !row.megakernel) return 0;
    return row.perLightSample ? row.bytes * shadowSamples : row.bytes;
}

// How many paths a wave holds: as many as memory (and `pathStateBudget`
// bytes of path state) allows up to the setting, rounded so that a wave holds
// whole samples of every pixel (or, for images larger than a wave, a whole
// sample is split into equal waves).
uint32_t pathsPerWave(const RenderSettings& s, KernelForm form, uint32_t shadowSamples, const vk::DeviceInfo& device,
                      uint64_t pixels, uint64_t pathStateBudget) {
    const uint64_t total = pathStateBytes(form, shadowSamples);
    uint64_t largest = 1;
    for (const PathBufferRow& row : PATH_BUFFERS) largest = std::max(largest, bytesPerPath(row, form, shadowSamples));
    uint64_t limit = s.maxPathsInFlight.value_or(defaultPathsInFlight(device));
    limit = std::min<uint64_t>(limit, device.deviceLocalMemory / 4 / total);
    limit = std::min<uint64_t>(limit, pathStateBudget / total);
    // The largest per-path array must fit one storage-buffer binding.
    limit = std::min<uint64_t>(limit, device.maxStorageBufferRange / largest);
    // One dispatch must reach every path of a wave, and every shadow ray of
    // the shadow stage (lavapipe allows 65535 workgroups).
    limit = std::min<uint64_t>(limit, uint64_t(device.maxWorkgroupCount[0]) * s.workgroupSize /
                                          std::max<uint32_t>(shadowSamples, 1));
    limit = std::max<uint64_t>(limit, 1);
    // The accumulate stage loops over a pixel's samples in the wave, and
    // lavapipe cuts every shader loop at 65535 iterations.
    constexpr uint64_t MAX_SAMPLES_PER_WAVE = 65535;
    if (pixels <= limit)
        return uint32_t(pixels * std::min<uint64_t>({limit / pixels, s.samplesPerPixel, MAX_SAMPLES_PER_WAVE}));
    const uint64_t wavesPerSample = (pixels + limit - 1) / limit;
    return uint32_t((pixels + wavesPerSample - 1) / wavesPerSample);
}

// Pixels per film window: as many as one storage-buffer binding holds
// (maxStorageBufferRange) and one dispatch of accumulate reaches (the
// device's workgroup count), or settings.filmWindowPixels if smaller.
uint32_t filmWindowPixels(const RenderSettings& s, const vk::DeviceInfo& device) {
    uint64_t limit = device.maxStorageBufferRange / sizeof(shared::FilmPixel);
    limit = std::min<uint64_t>(limit, uint64_t(device.maxWorkgroupCount[0]) * s.workgroupSize);
    if (s.filmWindowPixels) limit = std::min<uint64_t>(limit, s.filmWindowPixels);
    return uint32_t(std::clamp<uint64_t>(limit, 1, UINT32_MAX));
}

}  // namespace

uint64_t pathStateBytes(KernelForm form, uint32_t shadowRaysPerVertex) {
    uint64_t total = 0;
    for (const PathBufferRow& row : PATH_BUFFERS) total += bytesPerPath(row, form, shadowRaysPerVertex);
    return total;
}

KernelForm defaultKernelForm(const vk::DeviceInfo& device) {
    // lavapipe (a "cpu" device): the megakernel, 1.0x to 1.46x the wavefront's
    // paths per second on the bundled and shared scenes. Other types keep the
    // wavefront until measured on them (no GPU was lent yet).
    return device.type == "cpu" ? KernelForm::Megakernel : KernelForm::Wavefront;
}

uint32_t defaultPathsInFlight(const vk::DeviceInfo& device) {
    // An H200 (CBspheres 800x600, -m 4, the wavefront): 1.2 Gpaths/s with
    // 2^20 paths in flight, 1.6 with 2^21, 1.9 with 2^22, 2.2 with 2^23 and
    // 2.3 with 2^24 (2.3 GB of path state; pathsPerWave still keeps it to a
    // quarter of the device's memory). lavapipe: 2^22 ran 0.99x (the
    // megakernel) and 1.05x (the wavefront) of 2^20. Other types keep 2^20
    // until measured.
    return device.type == "discrete" ? 1u << 24 : 1u << 20;
}

struct GpuRenderer::Resources {
    uint32_t pathCount = 0;  // paths in flight (the wave size)
    bool shadowStage = false;
    vk::Buffer sceneInfo, camera, counters, placeholder;
    // The film in windows of consecutive pixels, each within one storage
    // binding and one dispatch (shared/wavefront.h WavePush.filmFirstPixel),
    // with accumulate's descriptor set for each.
    uint32_t filmWindowPixels = 0;
    std::vector<vk::Buffer> film;
    std::vector<vk::DescriptorSet> accumulateSets;
    std::map<uint32_t, vk::Buffer> pathBuffers;  // by binding, the rows of PATH_BUFFERS in use
    std::unique_ptr<vk::Kernel> generate, queueDispatch, intersect, shade, shadow, megakernel, accumulate;
    vk::DescriptorSet generateSet, queueDispatchSet, intersectSet, shadeSet, shadowSet, megakernelSet;

    uint64_t filmBytes() const {
        uint64_t bytes = 0;
        for (const vk::Buffer& window : film) bytes += window.size();
        return bytes;
    }
};

GpuRenderer::GpuRenderer(vk::Context& context, const scene::Scene& scene, const RenderSettings& settings)
    : m_context(context), m_settings(settings), m_constructed(Clock::now()), m_tables(buildSceneTables(scene)) {
    const shared::Camera camera = scene::makeGpuCamera(m_tables.camera, settings.width, settings.height);
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
    // maxDeviceMemoryBytes: the path state gets what the scene and the film leave.
    uint64_t pathStateBudget = UINT64_MAX;
    if (settings.maxDeviceMemoryBytes) {
        const uint64_t taken = m_scene.bytes() + pixels * sizeof(shared::FilmPixel);
        const uint64_t left = *settings.maxDeviceMemoryBytes - std::min(taken, *settings.maxDeviceMemoryBytes);
        const uint64_t fewest = std::min<uint64_t>(settings.workgroupSize, pixels * settings.samplesPerPixel);
        if (left / pathStateBytes(m_form, shadowSamples) < fewest)
            throw InputError(fmt::format(
                "--max-device-memory {:.3g} MiB: the scene and the film take {:.3g} MiB, leaving room for fewer "
                "than {} paths in flight",
                *settings.maxDeviceMemoryBytes / (1024.0 * 1024.0), taken / (1024.0 * 1024.0), fewest));
        pathStateBudget = left;
    }
    uint32_t w = pathsPerWave(settings, m_form, shadowSamples, context.info(), pixels, pathStateBudget);
    // The SceneInfo, then the guide spheres it counts (stages/lib/scene_access.glsl).
    std::vector<std::byte> sceneInfoBytes(sizeof(info) + info.guideSphereCount * sizeof(glm::vec4));
    std::memcpy(sceneInfoBytes.data(), &info, sizeof(info));
    if (info.guideSphereCount > 0)
        std::memcpy(sceneInfoBytes.data() + sizeof(info), m_tables.guideSpheres.data(),
                    info.guideSphereCount * sizeof(glm::vec4));
    r->sceneInfo = vk::Buffer::fromSpan(context, std::span(sceneInfoBytes), "sceneInfo");
    r->camera = vk::Buffer::fromSpan(context, std::span(&camera, 1), "camera");
    r->counters = vk::Buffer(context, sizeof(shared::QueueCounters), vk::MemoryKind::DeviceLocal, "counters");
    r->filmWindowPixels = filmWindowPixels(settings, context.info());
    for (uint64_t first = 0; first < pixels; first += r->filmWindowPixels) {
        const uint64_t windowPixels = std::min<uint64_t>(r->filmWindowPixels, pixels - first);
        r->film.emplace_back(context, windowPixels * sizeof(shared::FilmPixel), vk::MemoryKind::DeviceLocal, "film");
    }
    r->placeholder = vk::Buffer(context, 4, vk::MemoryKind::DeviceLocal, "placeholder");

    const GpuScene& g = m_scene;
    std::map<uint32_t, const vk::Buffer*> buffers = {
        {VKP_WF_SCENE_INFO, &r->sceneInfo},
        {VKP_WF_BVH_NODES, &g.bvh.nodeBinding()},
        {VKP_WF_BVH_PRIMITIVES, &g.bvh.primitiveBinding()},
        {VKP_WF_MATERIALS, &g.materials},
        {VKP_WF_LIGHTS, &g.binding(g.lights)},
        {VKP_WF_LIGHT_ALIAS, &g.binding(g.lightAlias)},
        {VKP_WF_PRIMITIVE_LIGHT, &g.binding(g.primitiveLight)},
        {VKP_WF_ENV_ALIAS, &g.binding(g.envAlias)},
        {VKP_WF_ENV_RADIANCE, &g.binding(g.envRadiance)},
        {VKP_WF_TRIANGLE_VERTICES, &g.binding(g.triangleVertices)},
        {VKP_WF_VERTEX_NORMALS, &g.binding(g.vertexNormals)},
        {VKP_WF_VERTEX_TEXCOORDS, &g.binding(g.vertexTexcoords)},
        {VKP_WF_VERTEX_COLORS, &g.binding(g.vertexColors)},
        {VKP_WF_VERTEX_TANGENTS, &g.binding(g.vertexTangents)},
        {VKP_WF_TEXTURES, &g.textures},
        {VKP_WF_TEXTURE_SLOTS, &g.textureSlots},
        {VKP_WF_TEXELS, &g.binding(g.texels)},
        {VKP_WF_MATERIAL_ALPHA, &g.materialAlpha},
        {VKP_WF_CAMERA, &r->camera},
        {VKP_WF_COUNTERS, &r->counters},
        {VKP_WF_FILM, &r->film.front()},
        {VKP_WF_SCENE_ADDRESSES, &g.addresses},
    };
    m_memory = {{"scene", g.bytes()}, {"path state", 0}, {"film", r->filmBytes()}};
    // The heap a device reports is shared with other programs and its
    // driver, so a wave that should fit may not: out of memory, the paths in
    // flight are halved (and rounded as pathsPerWave rounds them) until the
    // buffers fit, down to one workgroup's worth. The image does not depend
    // on the wave size. (lavapipe never runs out here: its device memory is
    // one file, grown and mapped on demand, so an address-space limit makes
    // it crash later rather than fail an allocation. maxDeviceMemoryBytes
    // bounds a render up front instead.)
    const uint32_t asked = w;
    for (;;) {
        try {
            for (const PathBufferRow& row : PATH_BUFFERS) {
                const uint64_t bytes = bytesPerPath(row, m_form, shadowSamples) * w;
                if (bytes == 0) {
                    buffers[row.binding] = &r->placeholder;
                    continue;
                }
                auto [it, inserted] = r->pathBuffers.emplace(
                    row.binding, vk::Buffer(context, bytes, vk::MemoryKind::DeviceLocal, row.name));
                buffers[row.binding] = &it->second;
                m_memory[1].bytes += bytes;
            }
            break;
        } catch (const vk::VulkanError& e) {
            if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY && e.result() != VK_ERROR_OUT_OF_HOST_MEMORY) throw;
            r->pathBuffers.clear();
            m_memory[1].bytes = 0;
            RenderSettings fewer = settings;
            fewer.maxPathsInFlight = w / 2;
            const uint32_t next = pathsPerWave(fewer, m_form, shadowSamples, context.info(), pixels, pathStateBudget);
            if (next < std::min(settings.workgroupSize, asked) || next >= w)
                throw vk::VulkanError(e.result(), fmt::format("out of device memory for the path state of {} paths in "
                                                              "flight ({} asked): {}",
                                                              w, asked, e.what()));
            w = next;
        }
    }
    if (w < asked)
        std::fprintf(stderr, "vkpath: warning: out of device memory for %u paths in flight: %u instead\n", asked, w);
    r->pathCount = w;

    // ---- pipelines: specialised to the render's features (the on-disk pipeline
    // cache keeps each feature set's) ------------------------------------------------
    const auto start = Clock::now();
    const vk::KernelOptions options{.workgroupSize = settings.workgroupSize};
    vk::KernelOptions sceneOptions = options;
    sceneOptions.specialization = {bvh::sceneAccessConstant(m_scene.byAddress), {VKP_SPEC_FEATURES, m_features}};
    std::vector<std::pair<const vk::Kernel*, const vk::DescriptorSet*>> built;
    auto build = [&](const char* name, const vk::KernelOptions& o, vk::DescriptorSet& set) {
        auto kernel = std::make_unique<vk::Kernel>(context, name, o);
        set = kernel->bindDeclared(buffers);
        built.emplace_back(kernel.get(), &set);
        return kernel;
    };
    const vk::KernelOptions dispatchOptions{.workgroupSize = 1, .specialization = {{1, settings.workgroupSize}}};
    r->queueDispatch = build("queue_dispatch", dispatchOptions, r->queueDispatchSet);
    r->accumulate = std::make_unique<vk::Kernel>(context, "accumulate", options);
    for (const vk::Buffer& window : r->film) {
        buffers[VKP_WF_FILM] = &window;
        r->accumulateSets.push_back(r->accumulate->bindDeclared(buffers));
    }
    buffers[VKP_WF_FILM] = &r->film.front();
    built.emplace_back(r->accumulate.get(), &r->accumulateSets.front());
    if (m_form == KernelForm::Megakernel) {
        r->megakernel = build("megakernel", sceneOptions, r->megakernelSet);
    } else {
        r->generate = build("generate", sceneOptions, r->generateSet);
        r->intersect = build("intersect", sceneOptions, r->intersectSet);
        r->shade = build("shade", sceneOptions, r->shadeSet);
        if (r->shadowStage) r->shadow = build("shadow", sceneOptions, r->shadowSet);
    }
    // Drivers may compile a pipeline at its first dispatch (lavapipe from Mesa
    // 25 does, for seconds): one empty dispatch of each, so that the time is
    // counted here and not in the first wave. With no paths every kernel
    // returns at once: the queues are empty (render() clears the counters again).
    r->counters.clear();
    m_context.submit([&](VkCommandBuffer cmd) {
        const shared::WavePush empty{0, 0, 0, 0, VKP_TALLY_RAYS};
        const auto push = std::as_bytes(std::span(&empty, 1));
        for (const auto& [kernel, set] : built) {
            kernel->record(cmd, *set, 1, push);
            vk::computeBarrier(cmd);
        }
    });
    m_pipelines = uint32_t(built.size());
    m_pipelineMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    m_setupMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - m_constructed).count();
    m_resources = std::move(r);
}

GpuRenderer::~GpuRenderer() = default;

uint32_t GpuRenderer::pathsInFlight() const { return m_resources->pathCount; }

std::string GpuRenderer::describe() const {
    std::string memory;
    uint64_t total = 0;
    for (const MemoryGroup& group : m_memory) {
        memory += fmt::format("{}{} {:.1f} MiB", memory.empty() ? "" : ", ", group.name, group.bytes / (1024.0 * 1024.0));
        total += group.bytes;
    }
    return fmt::format(
        "kernels: {}, {} ({} pipelines in {:.0f} ms, ready {:.0f} ms after the scene was loaded); device memory {:.1f} "
        "MiB: {} ({} paths in flight)",
        kernelFormName(m_form),
        m_settings.specialize ? "specialised to " + describeFeatures(m_features) : std::string("general (--no-specialize)"),
        m_pipelines, m_pipelineMilliseconds, m_setupMilliseconds, total / (1024.0 * 1024.0), memory, pathsInFlight());
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
        throw std::out_of_range(fmt::format("samples [{}, {}): sample indices beyond 32 bits", samples.first,
                                            uint64_t(samples.first) + samples.count));
    const uint32_t bounces = s.maxDepth + 1;  // shading passes: hits at depth 0..maxDepth
    vk::TimestampPool timestamps(m_context, 3 + 5 * bounces);

    RenderResult result;
    result.pathsInFlight = r.pathCount;
    const RenderState before = resumedState(control, GPU_FILM_FORMAT, s.width, s.height, samples, r.filmBytes());
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
    auto state = [&](std::vector<std::byte> film, const shared::QueueCounters& counters, uint64_t done,
                     double seconds) {
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
    const uint32_t fewest = std::min(s.workgroupSize, r.pathCount);
    uint32_t wave = s.maxWaveMilliseconds ? fewest : r.pathCount;  // the most paths the next wave may hold
    auto nextWave = [&](uint32_t count, double milliseconds) {
        const double cap = *s.maxWaveMilliseconds;
        const double aimed = count * (0.75 * cap / std::max(milliseconds, 1e-3));
        if (milliseconds > cap) return uint32_t(std::clamp<double>(aimed, fewest, wave));
        if (milliseconds < cap / 2) return uint32_t(std::clamp<double>(aimed, wave, r.pathCount));
        return wave;
    };
    while (done < totalPaths) {
        // A wave holds whole samples of every pixel, or stays within one
        // sample, so that each whole sample ends a wave (stops, the time
        // budget and checkpoints come there) whatever the wave sizes.
        const uint64_t intoSample = done % pixels;
        const uint64_t fits = intoSample == 0 && wave >= pixels ? wave / pixels * pixels
                                                                : std::min<uint64_t>(wave, pixels - intoSample);
        const uint32_t count = uint32_t(std::min<uint64_t>(fits, totalPaths - done));
        const auto waveStart = Clock::now();
        auto pushFor = [&](uint32_t bounce, uint32_t mode) {
            shared::WavePush p{uint32_t(samples.first + done / pixels), uint32_t(done % pixels), count, bounce, mode};
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
            if (m_form == KernelForm::Megakernel) {
                const auto tally = pushFor(0, VKP_TALLY_RAYS);
                // Each invocation traces ceil(count / invocations) paths in turn;
                // lavapipe ends a shader loop after 65535 iterations, one bounce each.
                const uint32_t perInvocation = std::clamp<uint32_t>(s.megakernelPathsPerInvocation, 1, 65535 / bounces);
                const uint32_t invocations = (count + perInvocation - 1) / perInvocation;
                timed("megakernel", [&] { r.megakernel->record(cmd, r.megakernelSet, invocations, bytes(p0)); });
                timed("queue_dispatch", [&] { r.queueDispatch->record(cmd, r.queueDispatchSet, 1, bytes(tally)); });
            } else {
                timed("generate", [&] { r.generate->record(cmd, r.generateSet, count, bytes(p0)); });
                const VkDeviceSize rayArgs = offsetof(shared::QueueCounters, rayDispatch);
                const VkDeviceSize shadowArgs = offsetof(shared::QueueCounters, shadowDispatch);
                for (uint32_t bounce = 0; bounce < bounces; ++bounce) {
                    const auto rays = pushFor(bounce, VKP_PREPARE_RAYS);
                    const auto shadows = pushFor(bounce, VKP_PREPARE_SHADOWS);
                    timed("queue_dispatch", [&] { r.queueDispatch->record(cmd, r.queueDispatchSet, 1, bytes(rays)); });
                    timed("intersect", [&] { r.intersect->recordIndirect(cmd, r.intersectSet, r.counters, rayArgs, bytes(rays)); });
                    timed("shade", [&] { r.shade->recordIndirect(cmd, r.shadeSet, r.counters, rayArgs, bytes(rays)); });
                    if (!r.shadowStage) continue;
                    timed("queue_dispatch", [&] { r.queueDispatch->record(cmd, r.queueDispatchSet, 1, bytes(shadows)); });
                    timed("shadow", [&] { r.shadow->recordIndirect(cmd, r.shadowSet, r.counters, shadowArgs, bytes(shadows)); });
                }
            }
            timed("accumulate", [&] {
                for (size_t i = 0; i < r.film.size(); ++i) {
                    shared::WavePush window = p0;
                    window.filmFirstPixel = uint32_t(i * r.filmWindowPixels);
                    const uint32_t windowPixels = uint32_t(r.film[i].size() / sizeof(shared::FilmPixel));
                    r.accumulate->record(cmd, r.accumulateSets[i], windowPixels, bytes(window));
                }
            });
        });
        if (s.maxWaveMilliseconds)
            wave = nextWave(count, std::chrono::duration<double, std::milli>(Clock::now() - waveStart).count());
        for (const vk::TimedInterval& t : timestamps.results()) result.stageMilliseconds[t.name] += t.milliseconds;
        done += count;
        ++result.waves;
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        const uint32_t samplesDone = uint32_t(done / pixels);
        if (control.progress) control.progress({samplesDone, samples.count, seconds});
        // Stops, the time budget and checkpoints: at whole samples only.
        if (done % pixels != 0) continue;
        if (gate.ends(samplesDone, samples.count, seconds, result.stopped)) break;
        if (gate.checkpointDue(samplesDone, samples.count)) {
            control.checkpoint(state(filmBytes(), r.counters.download<shared::QueueCounters>().at(0), done, seconds));
            gate.checkpointed();
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.paths = done - uint64_t(before.samplesDone) * pixels;
    if (wave < r.pathCount) result.cappedWavePaths = wave;

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
