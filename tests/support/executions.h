// The three executions of the path loop (the GPU wavefront, the GPU
// megakernel, the CPU reference) checked against each other on one scene.
#pragma once

#include <gtest/gtest.h>

#include <cstring>

#include "image/image.h"
#include "image/statistics.h"
#include "reference/reference_renderer.h"
#include "scene/scene.h"
#include "support/gpu_render.h"
#include "wavefront/gpu_scene.h"

namespace vkpath::test {

// Whether two images hold the same bits.
inline bool sameBits(const image::Image& a, const image::Image& b) {
    return a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

// `settings` rendered by the CPU reference.
inline wavefront::RenderResult renderCpu(const scene::Scene& s,
                                         const wavefront::RenderSettings& settings) {
    return reference::ReferenceRenderer(wavefront::buildSceneTables(s), settings).render();
}

// The wavefront, the megakernel and the general kernel (--no-specialize)
// give the same bits for `settings`, with no non-finite sample, and the CPU
// reference with the next seed the same image: no 8 x 8 block rejected by
// the z-test at a 1% family-wise rate.
inline void expectEveryExecutionAgrees(const scene::Scene& s, wavefront::RenderSettings settings) {
    settings.kernel = wavefront::KernelForm::Wavefront;
    const auto wavefrontResult = renderGpu(s, settings);
    settings.kernel = wavefront::KernelForm::Megakernel;
    const auto megakernel = renderGpu(s, settings);
    settings.specialize = false;
    const auto general = renderGpu(s, settings);
    EXPECT_TRUE(sameBits(wavefrontResult.image, megakernel.image)) << "wavefront and megakernel";
    EXPECT_TRUE(sameBits(general.image, megakernel.image)) << "general and specialised kernels";
    EXPECT_EQ(megakernel.nonFiniteSamples, 0u);
    settings.specialize = true;
    settings.seed += 1;
    const auto cpu = renderCpu(s, settings);
    const image::BlockComparison z = image::compareBlocks(
        cpu.image, cpu.varianceOfMean, megakernel.image, megakernel.varianceOfMean, 8, 0.01);
    EXPECT_EQ(z.rejected, 0) << "CPU reference: worst |z| " << z.worstZ;
}

}  // namespace vkpath::test
