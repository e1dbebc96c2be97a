// The GPU wavefront path tracer. Each wave of paths is one command buffer:
//
//   generate -> for bounce 0..maxDepth:
//                 queue_dispatch(rays) -> intersect -> shade -> queue_dispatch(shadows) -> shadow
//            -> accumulate
//
// Queues alternate between bounces (rayQueue[bounce & 1], as in pbrt-v4's
// wavefront integrator) and every stage after generate is dispatched
// indirectly from counts on the device: the host only waits between waves.
#pragma once

#include <functional>
#include <memory>

#include "scene/scene.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/render_types.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::wavefront {

class WavefrontRenderer {
  public:
    WavefrontRenderer(vk::Context& context, const scene::Scene& scene, const RenderSettings& settings);
    ~WavefrontRenderer();
    WavefrontRenderer(const WavefrontRenderer&) = delete;
    WavefrontRenderer& operator=(const WavefrontRenderer&) = delete;

    // Samples [0, settings.samplesPerPixel).
    RenderResult render(const std::function<void(const RenderProgress&)>& progress = {});
    // The given samples of every pixel; (first + count) x pixels must fit in
    // 32 bits (std::out_of_range otherwise). The result holds their mean.
    RenderResult render(const SampleRange& samples, const std::function<void(const RenderProgress&)>& progress = {});

    const SceneTables& tables() const { return m_tables; }
    uint64_t sceneBytes() const { return m_scene.bytes(); }
    const GpuScene& scene() const { return m_scene; }

  private:
    struct Resources;
    vk::Context& m_context;
    RenderSettings m_settings;
    SceneTables m_tables;
    GpuScene m_scene;
    std::unique_ptr<Resources> m_resources;
};

}  // namespace vkpath::wavefront
