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
#include <map>
#include <optional>
#include <string>

#include "image/image.h"
#include "scene/scene.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::vk {
class Context;
}

namespace vkpath::wavefront {

struct RenderSettings {
    uint32_t width = 640;
    uint32_t height = 480;
    uint32_t samplesPerPixel = 16;
    uint32_t maxDepth = 8;          // pbrt-v4's meaning: 0 = emitters seen directly only
    uint32_t lightSamples = 1;      // light samples per diffuse vertex (-l)
    uint32_t rouletteDepth = 4;     // Russian roulette from this bounce on
    uint32_t seed = 0;
    std::optional<double> timeBudgetSeconds;  // stop after the wave that crosses it
    uint32_t workgroupSize = 64;
    uint32_t maxPathsInFlight = 1u << 20;     // upper bound; also limited by device memory
};

struct RenderProgress {
    uint32_t samplesDone;   // per pixel
    uint32_t samplesTotal;
    double seconds;
};

struct RenderResult {
    image::Image image;          // mean radiance per pixel
    image::Image varianceOfMean; // per channel: sample variance / samples (the variance AOV)
    uint32_t samplesPerPixel = 0;  // reached (less than asked when the time budget ran out)
    uint64_t nonFiniteSamples = 0;
    uint64_t paths = 0;
    uint32_t waves = 0;
    uint32_t pathsInFlight = 0;
    double seconds = 0;                         // wall clock of the waves
    std::map<std::string, double> stageMilliseconds;  // device time per stage
};

class WavefrontRenderer {
  public:
    WavefrontRenderer(vk::Context& context, const scene::Scene& scene, const RenderSettings& settings);
    ~WavefrontRenderer();
    WavefrontRenderer(const WavefrontRenderer&) = delete;
    WavefrontRenderer& operator=(const WavefrontRenderer&) = delete;

    RenderResult render(const std::function<void(const RenderProgress&)>& progress = {});

    const SceneTables& tables() const { return m_tables; }
    uint64_t sceneBytes() const { return m_scene.bytes(); }

  private:
    struct Resources;
    vk::Context& m_context;
    RenderSettings m_settings;
    SceneTables m_tables;
    GpuScene m_scene;
    std::unique_ptr<Resources> m_resources;
};

}  // namespace vkpath::wavefront
