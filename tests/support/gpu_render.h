// Renders for tests on the GPU path tracer (wavefront::GpuRenderer on the
// test context), with the settings of a square film made one way everywhere.
#pragma once

#include <cstdint>
#include <optional>

#include "scene/scene.h"
#include "support/test_context.h"
#include "wavefront/render_types.h"
#include "wavefront/renderer.h"

namespace vkpath::test {

// `settings` rendered on the GPU.
inline wavefront::RenderResult renderGpu(const scene::Scene& s,
                                         const wavefront::RenderSettings& settings) {
    wavefront::GpuRenderer renderer(context(), s, settings);
    return renderer.render();
}

// A width x height film of `spp` samples and at most `maxDepth` bounces;
// every other setting at RenderSettings' default.
inline wavefront::RenderSettings filmSettings(uint32_t width, uint32_t height, uint32_t spp,
                                              uint32_t maxDepth, uint32_t seed = 1,
                                              uint32_t lightSamples = 1) {
    wavefront::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.samplesPerPixel = spp;
    settings.maxDepth = maxDepth;
    settings.seed = seed;
    settings.lightSamples = lightSamples;
    return settings;
}

// filmSettings of a size x size film.
inline wavefront::RenderSettings squareSettings(uint32_t size, uint32_t spp, uint32_t maxDepth,
                                                uint32_t seed = 1, uint32_t lightSamples = 1) {
    return filmSettings(size, size, spp, maxDepth, seed, lightSamples);
}

// squareSettings on the GPU, with `sampler` where given (else the default).
inline wavefront::RenderResult render(
    const scene::Scene& s, uint32_t spp, uint32_t maxDepth, uint32_t size = 48, uint32_t seed = 1,
    uint32_t lightSamples = 1, std::optional<wavefront::SamplerKind> sampler = std::nullopt) {
    wavefront::RenderSettings settings = squareSettings(size, spp, maxDepth, seed, lightSamples);
    if (sampler) settings.sampler = *sampler;
    return renderGpu(s, settings);
}

}  // namespace vkpath::test
