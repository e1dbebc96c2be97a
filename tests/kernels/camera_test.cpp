// The camera stage: the generate kernel's rays equal generateCameraRay run on
// the CPU with the same RNG numbers: origins exactly, directions to a few ulp
// (the GPU may evaluate normalize and divisions with other rounding).
#include "scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shared/camera.h"
#include "shared/dimensions.h"
#include "shared/path_state.h"
#include "shared/rng.h"
#include "shared/scene_data.h"
#include "shared/wavefront.h"
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

    // The wavefront's generate stage, for the wave holding sample
    // `sampleIndex` of every pixel (path = sampleIndex * pixels + pixel).
    shared::SceneInfo info{};
    info.seed = seed;
    info.width = width;
    info.height = height;
    vk::Buffer infoBuffer = vk::Buffer::fromSpan(context, std::span(&info, 1));
    vk::Buffer cameraBuffer = vk::Buffer::fromSpan(context, std::span(&gpuCamera, 1));
    vk::Buffer rays(context, count * sizeof(shared::Ray));
    vk::Buffer throughput(context, count * sizeof(glm::vec3)),
        radiance(context, count * sizeof(glm::vec3));
    vk::Buffer vertices(context, count * sizeof(shared::PathVertex)),
        queues(context, 3 * count * sizeof(uint32_t));
    vk::Buffer counters(context, sizeof(shared::QueueCounters));
    vk::Buffer noPixelList(context, sizeof(glm::uvec2));     // a uniform wave reads no list
    vk::Buffer noAovs(context, sizeof(shared::PathAov));     // SceneInfo::aovs is 0
    vk::Buffer wavelengths(context, count * sizeof(float));  // the general kernel keeps them
    vk::Kernel generate(context, "generate");
    generate.dispatch(count,
                      {{VKP_WF_SCENE_INFO, &infoBuffer},
                       {VKP_WF_CAMERA, &cameraBuffer},
                       {VKP_WF_RAYS, &rays},
                       {VKP_WF_THROUGHPUT, &throughput},
                       {VKP_WF_RADIANCE, &radiance},
                       {VKP_WF_VERTEX, &vertices},
                       {VKP_WF_QUEUES, &queues},
                       {VKP_WF_COUNTERS, &counters},
                       {VKP_WF_PIXEL_LIST, &noPixelList},
                       {VKP_WF_PATH_AOV, &noAovs},
                       {VKP_WF_PATH_WAVELENGTH, &wavelengths}},
                      shared::WavePush{sampleIndex, 0, count, 0, 0});
    const auto gpu = rays.download<shared::Ray>();
    // Every path starts alive in ray queue 0 with throughput 1.
    EXPECT_EQ(counters.download<shared::QueueCounters>()[0].rayCount0, count);
    for (const glm::vec3& t : throughput.download<glm::vec3>()) ASSERT_EQ(t, glm::vec3(1.0f));

    // A direction component of magnitude ~1 has ulp 2^-23 ~ 1.2e-7; allow 4 ulp.
    constexpr float TOLERANCE = 4.8e-7f;
    float worst = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const glm::uvec2 xy(i % width, i / width);
        const auto key = shared::makeRngKey(i, sampleIndex, seed);
        const shared::Ray cpu = shared::generateCameraRay(
            gpuCamera, xy, shared::rngUniform2(key, VKP_DIM_PIXEL_JITTER));
        ASSERT_EQ(gpu[i].origin, cpu.origin) << "pixel " << i;
        ASSERT_EQ(gpu[i].pixel, i);
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(gpu[i].direction[c] - cpu.direction[c]));
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
