#include "wavefront/pipeline_set.h"

#include <algorithm>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>

#include "shared/bindings.h"
#include "shared/features.h"
#include "vk/context.h"
#include "wavefront/kernel_features.h"

namespace vkpath::wavefront {
namespace {

std::span<const std::byte> bytes(const shared::WavePush& p) {
    return std::as_bytes(std::span(&p, 1));
}

// A kernel that reads the scene, as its build for the render's feature
// profile (profiledKernel).
std::string profiled(const char* kernel, const PipelineSetup& setup) {
    return profiledKernel(kernel, specializedFeatures(setup.sceneSpecialization));
}

// A kernel that traces rays, as its variant for the traversal and for
// features that may include instances (bvh::tracingKernel), in the build for
// the render's feature profile.
std::string tracing(const char* kernel, const PipelineSetup& setup) {
    const uint64_t features = specializedFeatures(setup.sceneSpecialization);
    const bool instances = (features & VKP_FEATURE_INSTANCES) != 0;
    return profiledKernel(bvh::tracingKernel(kernel, setup.traversal, instances), features);
}

}  // namespace

PipelineSet::PipelineSet(vk::Context& context, const PipelineSetup& setup,
                         std::map<uint32_t, const vk::Buffer*> bindings,
                         const std::vector<vk::Buffer>& film,
                         const std::vector<vk::Buffer>& filmOdd,
                         const std::vector<vk::Buffer>& filmAov, vk::Buffer& counters)
    : m_setup(setup) {
    const vk::KernelOptions options{.workgroupSize = setup.workgroupSize};
    vk::KernelOptions sceneOptions = options;
    sceneOptions.specialization = setup.sceneSpecialization;
    auto build = [&](const std::string& name, const vk::KernelOptions& o, vk::DescriptorSet& set) {
        auto kernel = std::make_unique<vk::Kernel>(context, name, o);
        set = kernel->bindDeclared(bindings);
        m_built.emplace_back(kernel.get(), &set);
        return kernel;
    };
    const vk::KernelOptions dispatchOptions{.workgroupSize = 1,
                                            .specialization = {{1, setup.workgroupSize}}};
    m_queueDispatch = build("queue_dispatch", dispatchOptions, m_queueDispatchSet);
    m_accumulate = std::make_unique<vk::Kernel>(context, "accumulate", options);
    const std::map<uint32_t, const vk::Buffer*> whole = bindings;
    for (size_t i = 0; i < film.size(); ++i) {
        bindings[VKP_WF_FILM] = &film[i];
        if (!filmOdd.empty()) bindings[VKP_WF_FILM_ODD] = &filmOdd[i];
        if (!filmAov.empty()) bindings[VKP_WF_FILM_AOV] = &filmAov[i];
        m_accumulateSets.push_back(m_accumulate->bindDeclared(bindings));
    }
    bindings = whole;
    m_built.emplace_back(m_accumulate.get(), &m_accumulateSets.front());
    if (setup.form == KernelForm::Megakernel) {
        m_megakernel = build(tracing("megakernel", setup), sceneOptions, m_megakernelSet);
    } else {
        m_generate = build("generate", sceneOptions, m_generateSet);
        m_intersect = build(tracing("intersect", setup), sceneOptions, m_intersectSet);
        m_shade = build(profiled("shade", setup), sceneOptions, m_shadeSet);
        if (setup.shadowStage)
            m_shadow = build(tracing("shadow", setup), sceneOptions, m_shadowSet);
    }
    // One empty dispatch of each; with no paths the queues are empty (the
    // renderer clears the counters again before its first wave).
    counters.clear();
    context.submit([&](VkCommandBuffer cmd) {
        const shared::WavePush empty{0, 0, 0, 0, VKP_TALLY_RAYS};
        for (const auto& [kernel, set] : m_built) {
            kernel->record(cmd, *set, 1, bytes(empty));
            vk::computeBarrier(cmd);
        }
    });
}

PipelineSet::~PipelineSet() = default;

void prewarmPipelines(vk::Context& context, const PipelineSetup& setup) {
    if (setup.traversal != bvh::Traversal::Compute)
        throw std::invalid_argument("prewarmPipelines: compute traversal only");
    // Large enough for every fixed-size block a kernel declares; with no
    // paths nothing past the counters and the scene's header is read.
    constexpr VkDeviceSize PLACEHOLDER_BYTES = 64 * 1024;
    vk::Buffer placeholder(context, PLACEHOLDER_BYTES, vk::MemoryKind::DeviceLocal,
                           "prewarm placeholder");
    vk::Buffer counters(context, sizeof(shared::QueueCounters), vk::MemoryKind::DeviceLocal,
                        "prewarm counters");
    std::map<uint32_t, const vk::Buffer*> bindings;
    for (uint32_t b = 0; b < VKP_WF_FIRST_FREE_BINDING; ++b) bindings[b] = &placeholder;
    std::vector<vk::Buffer> film;
    film.emplace_back(context, PLACEHOLDER_BYTES, vk::MemoryKind::DeviceLocal, "prewarm film");
    const PipelineSet set(context, setup, bindings, film, {}, {}, counters);
}

void PipelineSet::recordWave(VkCommandBuffer cmd, vk::TimestampPool& timestamps,
                             const shared::WavePush& wave, uint32_t bounces,
                             const vk::Buffer& counters, const std::vector<vk::Buffer>& film,
                             uint32_t filmWindowPixels,
                             const std::vector<uint32_t>& windowEntries) const {
    timestamps.reset(cmd);
    vk::computeBarrier(cmd);
    auto timed = [&](const char* name, auto&& work) {
        const uint32_t interval = timestamps.begin(cmd, name);
        work();
        timestamps.end(cmd, interval);
        vk::computeBarrier(cmd);
    };
    auto pushFor = [&](uint32_t bounce, uint32_t mode) {
        return shared::WavePush{.firstSample = wave.firstSample,
                                .firstPixel = wave.firstPixel,
                                .pathCount = wave.pathCount,
                                .bounce = bounce,
                                .mode = mode,
                                .pixelListLength = wave.pixelListLength};
    };
    const shared::WavePush p0 = pushFor(0, 0);
    if (m_setup.form == KernelForm::Megakernel) {
        const shared::WavePush tally = pushFor(0, VKP_TALLY_RAYS);
        // Each invocation traces ceil(count / invocations) paths in turn;
        // lavapipe ends a shader loop after 65535 iterations, one bounce each.
        const uint32_t perInvocation =
            std::clamp<uint32_t>(m_setup.megakernelPathsPerInvocation, 1, 65535 / bounces);
        const uint32_t invocations = (wave.pathCount + perInvocation - 1) / perInvocation;
        timed("megakernel",
              [&] { m_megakernel->record(cmd, m_megakernelSet, invocations, bytes(p0)); });
        timed("queue_dispatch",
              [&] { m_queueDispatch->record(cmd, m_queueDispatchSet, 1, bytes(tally)); });
    } else {
        timed("generate",
              [&] { m_generate->record(cmd, m_generateSet, wave.pathCount, bytes(p0)); });
        const VkDeviceSize rayArgs = offsetof(shared::QueueCounters, rayDispatch);
        const VkDeviceSize shadowArgs = offsetof(shared::QueueCounters, shadowDispatch);
        for (uint32_t bounce = 0; bounce < bounces; ++bounce) {
            const shared::WavePush rays = pushFor(bounce, VKP_PREPARE_RAYS);
            const shared::WavePush shadows = pushFor(bounce, VKP_PREPARE_SHADOWS);
            timed("queue_dispatch",
                  [&] { m_queueDispatch->record(cmd, m_queueDispatchSet, 1, bytes(rays)); });
            timed("intersect", [&] {
                m_intersect->recordIndirect(cmd, m_intersectSet, counters, rayArgs, bytes(rays));
            });
            timed("shade", [&] {
                m_shade->recordIndirect(cmd, m_shadeSet, counters, rayArgs, bytes(rays));
            });
            if (!m_setup.shadowStage) continue;
            timed("queue_dispatch",
                  [&] { m_queueDispatch->record(cmd, m_queueDispatchSet, 1, bytes(shadows)); });
            timed("shadow", [&] {
                m_shadow->recordIndirect(cmd, m_shadowSet, counters, shadowArgs, bytes(shadows));
            });
        }
    }
    timed("accumulate", [&] {
        for (size_t i = 0; i < film.size(); ++i) {
            shared::WavePush window = p0;
            window.filmFirstPixel = uint32_t(i * filmWindowPixels);
            uint32_t threads = uint32_t(film[i].size() / sizeof(shared::FilmPixel));
            if (wave.pixelListLength > 0) {  // one thread per list entry in the window
                window.listFirstEntry = windowEntries[i];
                threads = windowEntries[i + 1] - windowEntries[i];
                if (threads == 0) continue;
            }
            m_accumulate->record(cmd, m_accumulateSets[i], threads, bytes(window));
        }
    });
}

}  // namespace vkpath::wavefront
