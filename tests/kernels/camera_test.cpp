// The camera stage: the generate kernel's rays equal generateCameraRay run on
// the CPU with the same RNG numbers: origins exactly, directions to a few ulp
// (the GPU may evaluate normalize and divisions with other rounding).
#include <gtest/gtest.h>

#include <cmath>

#include "scene/camera.h"
#include "shared/bindings.h"
#include "shared/camera.h"
#include "shared/dimensions.h"
#include "shared/rng.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;

TEST(CameraStage, GpuRaysMatchCpu) {
    vk::Context& context = test::context();
    scene::Camera camera;
    camera.position = {1.5f, -2.0f, 7.25f};
    camera.target = {0.0f, 0.5f, 0.0f};
    camera.up = {0.0f, 1.0f, 0.0f};
    camera.xfovDegrees = 47.0f;
    const uint32_t width = 333, height = 217;  // odd sizes: no symmetry hides an index error
    const shared::Camera gpuCamera = scene::makeGpuCamera(camera, width, height);
    const uint32_t count = width * height, seed = 1234, sampleIndex = 5;

    vk::Buffer cameraBuffer = vk::Buffer::fromSpan(context, std::span(&gpuCamera, 1));
    vk::Buffer rays(context, count * sizeof(shared::Ray));
    vk::Kernel generate(context, "generate");
    generate.dispatch(count, {{VKP_GENERATE_BINDING_CAMERA, &cameraBuffer}, {VKP_GENERATE_BINDING_RAYS, &rays}},
                      shared::GeneratePush{0, count, sampleIndex, seed});
    const auto gpu = rays.download<shared::Ray>();

    // A direction component of magnitude ~1 has ulp 2^-23 ~ 1.2e-7; allow 4 ulp.
    constexpr float TOLERANCE = 4.8e-7f;
    float worst = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const glm::uvec2 xy(i % width, i / width);
        const auto key = shared::makeRngKey(i, sampleIndex, seed);
        const shared::Ray cpu =
            shared::generateCameraRay(gpuCamera, xy, shared::rngUniform2(key, VKP_DIM_PIXEL_JITTER));
        ASSERT_EQ(gpu[i].origin, cpu.origin) << "pixel " << i;
        ASSERT_EQ(gpu[i].pixel, i);
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(gpu[i].direction[c] - cpu.direction[c]));
    }
    EXPECT_LE(worst, TOLERANCE);
}

TEST(CameraStage, FieldOfViewWidensTheNarrowerAxis) {
    scene::Camera camera;
    camera.xfovDegrees = 90.0f;
    camera.aspect = 2.0f;  // the camera frames 2:1
    // A 2:1 film keeps both: tan(45) = 1 horizontally, 0.5 vertically.
    auto wide = scene::makeGpuCamera(camera, 200, 100);
    EXPECT_NEAR(glm::length(wide.right), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(wide.up), 0.5f, 1e-6f);
    // A square film is narrower: the vertical extent grows to keep the width.
    auto square = scene::makeGpuCamera(camera, 100, 100);
    EXPECT_NEAR(glm::length(square.right), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::length(square.up), 1.0f, 1e-6f);
    // A 4:1 film is wider: the horizontal extent grows to keep the height.
    auto wider = scene::makeGpuCamera(camera, 400, 100);
    EXPECT_NEAR(glm::length(wider.right), 2.0f, 1e-6f);
    EXPECT_NEAR(glm::length(wider.up), 0.5f, 1e-6f);
}

}  // namespace
