// The GPU path tracer, in either form of shared/integrator.h's loop. Each wave
// of paths is one command buffer:
//
//   wavefront:  generate -> for bounce 0..maxDepth:
//                 queue_dispatch(rays) -> intersect -> shade [-> queue_dispatch(shadows) -> shadow]
//               -> accumulate
//   megakernel: megakernel -> queue_dispatch(tally) -> accumulate
//
// Wavefront queues alternate between bounces (rayQueue[bounce & 1], as in
// pbrt-v4's wavefront integrator) and every stage after generate is
// dispatched indirectly from counts on the device: the host only waits
// between waves. The kernels are specialised to the render's features
// (shared/features.h); the shadow stage is recorded only where a shadow ray
// can be queued.
#pragma once

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/pipeline_set.h"
#include "wavefront/render_types.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::vk {
class Context;
struct DeviceInfo;
}  // namespace vkpath::vk

namespace vkpath::wavefront {

// Device memory a render allocated, by group.
struct MemoryGroup {
    std::string name;  // "scene", "path state", "film"
    uint64_t bytes = 0;
};

class GpuRenderer {
  public:
    // Where the device is out of memory for the per-path buffers, fewer paths
    // are in flight (pathsInFlight(); a warning on stderr says so).
    GpuRenderer(vk::Context& context, const scene::Scene& scene, const RenderSettings& settings);
    // From tables already built (buildSceneTables), for several renders of one
    // scene with other settings (render --auto's pilots): no second BVH build.
    GpuRenderer(vk::Context& context, SceneTables tables, const RenderSettings& settings);
    ~GpuRenderer();
    GpuRenderer(const GpuRenderer&) = delete;
    GpuRenderer& operator=(const GpuRenderer&) = delete;

    // Samples [0, settings.samplesPerPixel).
    RenderResult render(const std::function<void(const RenderProgress&)>& progress = {});
    // The given samples of every pixel; sample indices are 32-bit, so first +
    // count must be at most 2^32 (std::out_of_range otherwise). The result
    // holds their mean.
    RenderResult render(const SampleRange& samples,
                        const std::function<void(const RenderProgress&)>& progress = {});
    // The same with stops, checkpoints and resuming (RenderControl); throws
    // InputError for a state this renderer cannot continue.
    RenderResult render(const SampleRange& samples, const RenderControl& control);

    // The tables as the renderer keeps them once the device holds the scene:
    // without the arrays that uploading released (releaseUploaded).
    const SceneTables& tables() const { return m_tables; }
    // describeMemory's line for the scene as uploaded.
    const std::string& describeSceneMemory() const { return m_sceneMemory; }
    uint64_t sceneBytes() const { return m_scene.bytes(); }
    const GpuScene& scene() const { return m_scene; }
    KernelForm form() const { return m_form; }
    bvh::Traversal traversal() const { return m_traversal; }
    uint64_t features() const { return m_features; }  // VKP_FEATURE_* bits of the pipelines
    double pipelineMilliseconds() const {
        return m_pipelineMilliseconds;
    }  // creating them (cached or not)
    // From the constructor's start (the scene loaded) to ready for the first
    // wave: scene tables and BVH, upload, buffers, pipelines.
    double setupMilliseconds() const { return m_setupMilliseconds; }
    const std::vector<MemoryGroup>& memory() const { return m_memory; }
    uint32_t pathsInFlight() const;
    // One line: the kernel form, the features the pipelines were built for and
    // how long that took, and the device memory by group.
    std::string describe() const;
    // Whether the pipelines were compiled while the BVH was built (a large
    // scene's, whose tables before the BVH foretold the render's pipelines).
    bool pipelinesPrewarmed() const { return m_prewarmed; }

  private:
    struct Resources;
    // Where the pipelines for the tables as they are before the BVH is built
    // can be foretold (a BVH large enough that its depth is certain), starts
    // compiling them on another thread (prewarmPipelines).
    void startPrewarm(const SceneTables& beforeBvh, const scene::Scene& scene);
    // The pipelines' setup for these features, scene access and light samples.
    PipelineSetup pipelineSetup(uint64_t features, bool byAddress, uint32_t lightSamples) const;
    void setUp();  // the constructors' work once the tables are built
    vk::Context& m_context;
    RenderSettings m_settings;
    std::chrono::steady_clock::time_point m_constructed;
    // The setup the prewarm compiles, and the prewarm (before m_tables, whose
    // building starts it; after the setup, which its thread may reset: a
    // constructor that throws waits for the thread before the setup goes).
    std::optional<PipelineSetup> m_prewarmSetup;
    bool m_prewarmed = false;
    std::future<void> m_prewarm;
    SceneTables m_tables;
    GpuScene m_scene;
    KernelForm m_form = KernelForm::Wavefront;
    bvh::Traversal m_traversal = bvh::Traversal::Compute;
    uint64_t m_features = 0;
    uint32_t m_pipelines = 0;
    double m_pipelineMilliseconds = 0;
    double m_setupMilliseconds = 0;
    std::vector<MemoryGroup> m_memory;
    std::string m_sceneMemory;
    std::unique_ptr<Resources> m_resources;
};

}  // namespace vkpath::wavefront
