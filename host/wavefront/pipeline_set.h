// The GPU renderer's kernels for one render: the pipelines of its kernel
// form, specialised to the render's features (the on-disk pipeline cache
// keeps each feature set's), each with its descriptor set, and the recording
// of one wave into a command buffer:
//
//   wavefront:  generate -> for bounce 0..maxDepth:
//                 queue_dispatch(rays) -> intersect -> shade [-> queue_dispatch(shadows) -> shadow]
//               -> accumulate (once per film window)
//   megakernel: megakernel -> queue_dispatch(tally) -> accumulate
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "shared/wavefront.h"
#include "vk/kernel.h"
#include "vk/timestamps.h"
#include "wavefront/render_types.h"

namespace vkpath::wavefront {

struct PipelineSetup {
    KernelForm form = KernelForm::Wavefront;
    bool shadowStage = false;  // the wavefront's shadow stage (a shadow ray can be queued)
    uint32_t workgroupSize = 64;
    // The scene kernels' specialisation: scene access and feature bits.
    std::vector<vk::SpecializationConstant> sceneSpecialization;
    uint32_t megakernelPathsPerInvocation = 1;           // RenderSettings'
    bvh::Traversal traversal = bvh::Traversal::Compute;  // of the kernels that trace rays

    bool operator==(const PipelineSetup&) const = default;
};

class PipelineSet {
  public:
    // Builds the form's pipelines and binds each its buffers from `bindings`
    // (binding -> buffer; the film's binding is set per window from `film`),
    // then runs one empty dispatch of each: drivers may compile a pipeline at
    // its first dispatch (lavapipe from Mesa 25 does, for seconds), and that
    // time belongs here, not to the first wave. `counters` is cleared
    // before (with no paths every kernel returns at once).
    // `filmOdd`: the odd stream's windows with two sample streams, else empty;
    // `filmAov`: the AOVs' windows when the render keeps them, else empty.
    PipelineSet(vk::Context& context, const PipelineSetup& setup,
                std::map<uint32_t, const vk::Buffer*> bindings, const std::vector<vk::Buffer>& film,
                const std::vector<vk::Buffer>& filmOdd, const std::vector<vk::Buffer>& filmAov,
                vk::Buffer& counters);
    ~PipelineSet();

    uint32_t count() const { return uint32_t(m_built.size()); }

    // Records one wave: the paths of `wave` (its bounce and mode unused) for
    // `bounces` shading passes, then their accumulation into every window of
    // `film` (windows of `filmWindowPixels`). Each kernel's dispatch is timed
    // by its name in `timestamps`. In an adaptive pass (wave.pixelListLength
    // > 0) `windowEntries` holds the first list entry of each window and,
    // last, the list's length.
    void recordWave(VkCommandBuffer cmd, vk::TimestampPool& timestamps,
                    const shared::WavePush& wave, uint32_t bounces, const vk::Buffer& counters,
                    const std::vector<vk::Buffer>& film, uint32_t filmWindowPixels,
                    const std::vector<uint32_t>& windowEntries) const;

  private:
    PipelineSetup m_setup;
    std::unique_ptr<vk::Kernel> m_generate, m_queueDispatch, m_intersect, m_shade, m_shadow,
        m_megakernel, m_accumulate;
    vk::DescriptorSet m_generateSet, m_queueDispatchSet, m_intersectSet, m_shadeSet, m_shadowSet,
        m_megakernelSet;
    std::vector<vk::DescriptorSet> m_accumulateSets;  // one per film window
    std::vector<std::pair<const vk::Kernel*, const vk::DescriptorSet*>> m_built;
};

// Builds the pipelines of `setup` and runs their empty dispatches on
// placeholder buffers, so that a PipelineSet of the same setup made later on
// `context` finds them compiled (Context::compiledKernel keeps them): the
// renderer does this while the BVH builds. It submits to the context's
// queue: no other thread may use the context meanwhile. Ray-query kernels
// need acceleration structures, which placeholders are not: compute
// traversal only.
void prewarmPipelines(vk::Context& context, const PipelineSetup& setup);

}  // namespace vkpath::wavefront
