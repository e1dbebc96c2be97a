// The registry of light types (shaders/shared/light_types.h) walked row by
// row: its numbers, feature bits and flags are what the kernels read; the
// host makes a light of every type from a scene; and every type's sample
// (through sampleLight's dispatch, the shared code compiled as C++) is what
// its flags say: a delta light's sample is delta, an area light's has the
// density areaLightPdf gives the point it landed on, and the environment is
// left to its caller. The lights' own statistics are sampling_test.cpp's.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>

#include "scene/scene.h"
#include "shared/lights.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"

namespace {

using namespace vkpath;

struct LightRow {
    uint32_t id;
    const char* label;
    uint64_t feature, shape;
    uint32_t flags;
};

constexpr LightRow LIGHT_ROWS[] = {
#define VKP_LIGHT_ROW(id, NAME, Type, label, feature, shape, flags) \
    {id, label, feature, shape, flags},
    VKP_LIGHT_TYPES(VKP_LIGHT_ROW)
#undef VKP_LIGHT_ROW
};

// A scene with a light of every type: an emissive triangle and sphere, a
// point, a spot and a directional light, and a constant environment.
scene::Scene everyLight() {
    scene::Scene s;
    scene::Material lamp;
    lamp.emission = glm::vec3(2.0f);
    s.materials = {scene::Material{}, lamp};
    scene::Mesh floor;
    floor.positions = {{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}};
    floor.triangles = {{0, 2, 1}, {0, 3, 2}};
    s.meshes.push_back(floor);
    scene::Mesh panel;  // facing down
    panel.positions = {{-1, 3, -1}, {1, 3, -1}, {0, 3, 1}};
    panel.triangles = {{0, 1, 2}};
    panel.material = 1;
    s.meshes.push_back(panel);
    s.spheres.push_back({"bulb", glm::vec3(2.0f, 2.0f, 0.0f), 0.3f, 1});
    s.pointLights.push_back({glm::vec3(-2.0f, 2.0f, 0.0f), glm::vec3(5.0f)});
    scene::SpotLight spot;
    spot.position = glm::vec3(0.0f, 2.5f, 2.0f);
    spot.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    spot.intensity = glm::vec3(5.0f);
    s.spotLights.push_back(spot);
    s.directionalLights.push_back({glm::vec3(0.3f, -1.0f, 0.1f), glm::vec3(1.0f)});
    s.environment = scene::Environment{};
    s.environment->color = glm::vec3(0.2f);
    return s;
}

TEST(LightRegistry, RowsAreNumberedInOrderWithUniqueLabels) {
    std::set<std::string> labels;
    ASSERT_EQ(std::size(LIGHT_ROWS), VKP_LIGHT_TYPE_COUNT);
    for (uint32_t i = 0; i < VKP_LIGHT_TYPE_COUNT; ++i) {
        const LightRow& row = LIGHT_ROWS[i];
        SCOPED_TRACE(row.label);
        EXPECT_EQ(row.id, i);
        EXPECT_TRUE(labels.insert(row.label).second);
        EXPECT_NE(row.feature, 0u);
        EXPECT_EQ(shared::lightTypeFeature(i), row.feature);
        EXPECT_EQ(shared::lightTypeFlags(i), row.flags);
        // An area light is a primitive's; the others are not.
        EXPECT_EQ(row.shape != 0u, (row.flags & VKP_LIGHT_IS_AREA) != 0u);
        EXPECT_FALSE((row.flags & VKP_LIGHT_IS_AREA) && (row.flags & VKP_LIGHT_IS_DELTA));
    }
    EXPECT_EQ(shared::possibleLightTypes(), (1u << VKP_LIGHT_TYPE_COUNT) - 1u);
}

TEST(LightRegistry, TheHostMakesEveryTypeAndItsFeatures) {
    const wavefront::SceneTables tables = wavefront::buildSceneTables(everyLight());
    const uint64_t features = wavefront::sceneFeatures(tables);
    for (const LightRow& row : LIGHT_ROWS) {
        SCOPED_TRACE(row.label);
        int count = 0;
        for (const shared::Light& light : tables.lights) count += light.type == row.id;
        EXPECT_EQ(count, 1) << "one light of each type";
        EXPECT_NE(features & row.feature, 0u);
        if (row.shape != 0u) {
            EXPECT_NE(features & row.shape, 0u);
        }
    }
}

TEST(LightRegistry, EveryTypeSamplesAsItsFlagsSay) {
    const wavefront::SceneTables tables = wavefront::buildSceneTables(everyLight());
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (const shared::Light& light : tables.lights) {
        const LightRow& row = LIGHT_ROWS[light.type];
        SCOPED_TRACE(row.label);
        int lit = 0;
        for (int i = 0; i < 1024; ++i) {
            // Points above the floor, in render space (the tables' space).
            const glm::vec3 p(-1.5f + 3.0f * uniform(rng), 0.2f + uniform(rng),
                              -1.5f + 3.0f * uniform(rng));
            const glm::vec3 origin = p - glm::vec3(tables.worldOrigin);
            const shared::LightSample s =
                shared::sampleLight(light, origin, glm::vec2(uniform(rng), uniform(rng)));
            if (row.id == VKP_LIGHT_ENVIRONMENT) {
                EXPECT_EQ(s.pdf, 0.0f) << "the environment is sampled by its caller";
                continue;
            }
            if (!(s.pdf > 0.0f) || s.radiance == glm::vec3(0.0f)) continue;
            ++lit;
            EXPECT_NEAR(glm::length(s.direction), 1.0f, 1e-5f);
            EXPECT_EQ(s.delta, (row.flags & VKP_LIGHT_IS_DELTA) != 0u);
            if (row.flags & VKP_LIGHT_IS_AREA) {
                const glm::vec3 x = origin + s.distance * s.direction;
                const float pdf = shared::areaLightPdf(light, origin, x, s.normal);
                EXPECT_NEAR(s.pdf, pdf, 1e-3f * pdf);
            }
        }
        if (row.id != VKP_LIGHT_ENVIRONMENT) {
            EXPECT_GT(lit, 256);
        }
    }
}

}  // namespace
