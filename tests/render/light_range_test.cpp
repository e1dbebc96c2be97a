// KHR_lights_punctual's range (shaders/shared/lights.h rangeWindow): a point
// or spot light's inverse square windowed by clamp(1 - (d / r)^4, 0, 1),
// nothing beyond r; a feature bit only where a light has one; and a floor
// under a ranged lamp renders it (GPU, direct light only: a point light's
// sample has no noise).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "reference/reference_renderer.h"
#include "scene/scene.h"
#include "shared/lights.h"
#include "support/gpu_render.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"

namespace {

using namespace vkpath;

float window(float distance, float range) {
    const float x = distance / range;
    return std::clamp(1.0f - x * x * x * x, 0.0f, 1.0f);
}

TEST(LightRange, WindowsTheInverseSquareAndEndsAtTheRange) {
    shared::Light point{};
    point.type = VKP_LIGHT_POINT;
    point.emission = glm::vec3(3.0f);
    point.radius = 2.0f;  // the range
    shared::Light spot = point;
    spot.type = VKP_LIGHT_SPOT;
    spot.p1 = glm::vec3(0.0f, -1.0f, 0.0f);
    spot.cosInner = 0.9f;
    spot.cosOuter = 0.5f;
    for (const float d : {0.25f, 1.0f, 1.5f, 1.99f, 2.0f, 3.0f}) {
        SCOPED_TRACE(d);
        const glm::vec3 p(0.0f, -d, 0.0f);  // on the spot's axis
        const float expected = 3.0f * window(d, 2.0f) / (d * d);
        EXPECT_NEAR(shared::sampleLight(point, p, glm::vec2(0.5f)).radiance.x, expected,
                    1e-6f * (1.0f + expected));
        EXPECT_NEAR(shared::sampleLight(spot, p, glm::vec2(0.5f)).radiance.x, expected,
                    1e-6f * (1.0f + expected));
        if (d >= 2.0f) {
            EXPECT_EQ(shared::sampleLight(point, p, glm::vec2(0.5f)).radiance, glm::vec3(0.0f));
        }
    }
    point.radius = 0.0f;  // none: the inverse square alone
    EXPECT_FLOAT_EQ(shared::sampleLight(point, glm::vec3(0, -3, 0), glm::vec2(0.5f)).radiance.x,
                    3.0f / 9.0f);
}

// A grey floor under a point light 0.5 m up, range 1 m, seen from 3 m above.
scene::Scene floorUnderRangedLamp(float xfovDegrees, float range) {
    scene::Scene s;
    s.materials.push_back(scene::Material{});  // diffuse, albedo 0.8
    scene::Mesh floor;
    floor.positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    floor.triangles = {{0, 2, 1}, {0, 3, 2}};
    s.meshes.push_back(floor);
    s.pointLights.push_back({glm::vec3(0.0f, 0.5f, 0.0f), glm::vec3(2.0f), range});
    s.camera.position = {0.0f, 3.0f, 0.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.up = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = xfovDegrees;
    return s;
}

TEST(LightRange, IsAFeatureOnlyWhereALightHasOne) {
    const auto features = [](const scene::Scene& s) {
        const wavefront::SceneTables t = wavefront::buildSceneTables(s);
        return wavefront::renderFeatures(t, wavefront::renderSceneInfo(t, {}));
    };
    EXPECT_TRUE(features(floorUnderRangedLamp(90.0f, 1.0f)) & VKP_FEATURE_LIGHT_RANGE);
    EXPECT_FALSE(features(floorUnderRangedLamp(90.0f, 0.0f)) & VKP_FEATURE_LIGHT_RANGE);
}

// 32 x 32, 16 spp, direct light only. Wide (90 degrees, 0.1875 m pixels):
// every pixel whose footprint lies beyond the range's circle on the floor
// (0.866 m from the lamp's foot) is exactly black, the lamp's foot is lit.
// Narrow (10 degrees, 0.016 m pixels): the four pixels at the foot within
// 1% of (albedo / pi) I cos / d^2 x the window at their centres (the
// footprint's spread of 1 / d^3 there is below 0.2%); the CPU reference
// gives the same within 1%.
TEST(LightRange, AFloorIsLitOnlyWithinTheRange) {
    wavefront::RenderSettings settings = test::squareSettings(32, 16, 1);
    const wavefront::RenderResult wide =
        test::renderGpu(floorUnderRangedLamp(90.0f, 1.0f), settings);
    const float pixel = 6.0f / 32.0f;
    int dark = 0;
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i) {
            const float x = -3.0f + (float(i) + 0.5f) * pixel,
                        z = -3.0f + (float(j) + 0.5f) * pixel;
            const float nx = std::max(std::abs(x) - pixel / 2, 0.0f);
            const float nz = std::max(std::abs(z) - pixel / 2, 0.0f);
            const glm::vec3 v = wide.image.pixels[size_t(j) * 32 + size_t(i)];
            if (nx * nx + nz * nz > 0.75f * 1.0001f) {
                EXPECT_EQ(v, glm::vec3(0.0f)) << "pixel " << i << ", " << j;
                ++dark;
            }
        }
    EXPECT_GT(dark, 900);
    EXPECT_GT(wide.image.pixels[16 * 32 + 16].x, 0.1f);

    const scene::Scene narrow = floorUnderRangedLamp(10.0f, 1.0f);
    const wavefront::RenderResult gpu = test::renderGpu(narrow, settings);
    const wavefront::RenderResult cpu = reference::ReferenceRenderer(narrow, settings).render();
    const float small = 2.0f * 3.0f * std::tan(5.0f * std::numbers::pi_v<float> / 180.0f) / 32.0f;
    for (const int j : {15, 16})
        for (const int i : {15, 16}) {
            const float x = (float(i) - 15.5f) * small, z = (float(j) - 15.5f) * small;
            const float d = std::sqrt(0.25f + x * x + z * z);
            const float expected =
                0.8f / std::numbers::pi_v<float> * 2.0f * (0.5f / d) / (d * d) * window(d, 1.0f);
            const size_t k = size_t(j) * 32 + size_t(i);
            EXPECT_NEAR(gpu.image.pixels[k].x, expected, 0.01f * expected) << i << ", " << j;
            EXPECT_NEAR(cpu.image.pixels[k].x, expected, 0.01f * expected) << i << ", " << j;
        }
}

}  // namespace
