// The light tree (shaders/shared/light_tree.h, host/wavefront/light_tree.h):
// the host's tree holds every light with power once, under its trail, with
// bounds that hold its children's; the walk's choices follow the
// probabilities that MIS reads back (chi-square, the shared code compiled as
// C++); a light it never chooses at a point cannot reach that point; and a
// render that chooses through it estimates the image that power sampling
// does (block z-tests on the GPU, both kernel forms, and the CPU reference).
#include "wavefront/light_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "image/statistics.h"
#include "reference/path_tracer_view.h"
#include "reference/reference_renderer.h"
#include "scene/scene.h"
#include "support/binding_limit.h"
#include "support/gpu_render.h"
#include "support/statistics.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"
#include "wavefront/render_types.h"

namespace {

using namespace vkpath;

// A grid x grid field of small square lamps (two triangles each, facing
// down, in four colours) 0.3 m over a 4 m floor, with an emissive sphere, a
// point and a spot light among them, and, unless `bounded` only, a
// directional light and a constant sky (the lights outside the tree),
// seen from above.
scene::Scene lampField(int grid, bool bounded = false) {
    scene::Scene s;
    s.materials.push_back(scene::Material{});  // the floor: grey diffuse
    const glm::vec3 colours[] = {{4, 2, 0.5}, {0.5, 1, 4}, {0.4, 3, 0.4}, {1, 1, 1}};
    for (const glm::vec3& c : colours) {
        scene::Material lamp;
        lamp.emission = c;
        s.materials.push_back(lamp);
    }
    scene::Mesh floor;
    floor.positions = {{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}};
    floor.triangles = {{0, 2, 1}, {0, 3, 2}};
    s.meshes.push_back(floor);
    const float pitch = 3.6f / float(grid), half = 0.2f * pitch;
    for (int row = 0; row < grid; ++row)
        for (int column = 0; column < grid; ++column) {
            const float x = -1.8f + (float(column) + 0.5f) * pitch;
            const float z = -1.8f + (float(row) + 0.5f) * pitch;
            scene::Mesh lamp;
            lamp.positions = {{x - half, 0.3f, z - half},
                              {x + half, 0.3f, z - half},
                              {x + half, 0.3f, z + half},
                              {x - half, 0.3f, z + half}};
            lamp.triangles = {{0, 1, 2}, {0, 2, 3}};  // counter-clockwise seen from below
            lamp.material = 1 + uint32_t(row * 3 + column) % 4;
            s.meshes.push_back(lamp);
        }
    s.spheres.push_back({"bulb", glm::vec3(0.5f, 0.6f, 0.5f), 0.1f, 1});
    s.pointLights.push_back({glm::vec3(-0.7f, 0.8f, 0.4f), glm::vec3(0.3f)});
    scene::SpotLight spot;
    spot.position = glm::vec3(0.2f, 1.0f, -0.9f);
    spot.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    spot.intensity = glm::vec3(0.5f);
    s.spotLights.push_back(spot);
    if (!bounded) {
        s.directionalLights.push_back({glm::vec3(0.3f, -1.0f, 0.1f), glm::vec3(0.2f)});
        s.environment = scene::Environment{};
        s.environment->color = glm::vec3(0.05f);
    }
    s.camera.position = {0.0f, 3.0f, 2.5f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 60.0f;
    return s;
}

bool contains(const shared::LightTreeNode& outer, const shared::LightTreeNode& inner) {
    return glm::all(glm::lessThanEqual(outer.boundsMin, inner.boundsMin)) &&
           glm::all(glm::greaterThanEqual(outer.boundsMax, inner.boundsMax));
}

// Walks every node below `index`: children's bounds inside their parent's,
// power their sum; returns the leaves' count.
size_t checkSubtree(const wavefront::LightTree& tree, uint32_t index) {
    const shared::LightTreeNode& node = tree.nodes.at(index);
    if (node.flags & VKP_LIGHT_NODE_LEAF) return 1;
    const shared::LightTreeNode &first = tree.nodes.at(index + 1),
                                &second = tree.nodes.at(node.index);
    EXPECT_TRUE(contains(node, first) && contains(node, second)) << "node " << index;
    EXPECT_NEAR(node.power, first.power + second.power, 1e-5f * node.power) << "node " << index;
    EXPECT_GE(node.cosNormals, -1.0f);
    return checkSubtree(tree, index + 1) + checkSubtree(tree, node.index);
}

// The leaf that `trail` leads to from the root.
uint32_t leafOfTrail(const wavefront::LightTree& tree, uint32_t trail) {
    uint32_t index = 0;
    for (uint32_t depth = 0; depth <= VKP_LIGHT_TREE_MAX_DEPTH; ++depth) {
        const shared::LightTreeNode& node = tree.nodes.at(index);
        if (node.flags & VKP_LIGHT_NODE_LEAF) return node.index;
        index = (trail >> depth) & 1u ? node.index : index + 1;
    }
    return VKP_NO_LIGHT;
}

TEST(LightTree, HoldsEveryLightOnceUnderItsTrail) {
    const wavefront::SceneTables t = wavefront::buildSceneTables(lampField(8));
    const wavefront::LightTree& tree = t.lightTree;
    // 128 lamp triangles, the sphere, the point and the spot in the tree; the
    // directional light and the sky after it.
    ASSERT_EQ(tree.trails.size(), 131u);
    ASSERT_EQ(t.lights.size(), 133u);
    EXPECT_EQ(tree.nodes.size(), 2 * tree.trails.size() - 1);
    EXPECT_EQ(checkSubtree(tree, 0), tree.trails.size());
    EXPECT_LE(tree.depth, VKP_LIGHT_TREE_MAX_DEPTH);
    for (uint32_t light = 0; light < tree.trails.size(); ++light)
        EXPECT_EQ(leafOfTrail(tree, tree.trails[light]), light);
    // The alias table's second part: the tree, then the two lights at infinity.
    EXPECT_EQ(t.lightAlias.size(), t.lights.size() + 3);
}

// Lights at x = 1.1^i: a cost that peels one light off at a time would nest
// them 299 deep; the tree splits by count where its depth would pass 31.
TEST(LightTree, StaysWithinItsDepthWhereTheCostWouldNestEveryLight) {
    std::vector<shared::Light> lights(300);
    std::vector<double> power(lights.size(), 1.0);
    for (size_t i = 0; i < lights.size(); ++i) {
        lights[i].type = VKP_LIGHT_POINT;
        lights[i].p0 = glm::vec3(std::pow(1.1f, float(i)), 0.0f, 0.0f);
    }
    power[7] = 0.0;  // no power: left out
    const wavefront::LightTree tree = wavefront::buildLightTree(lights, power);
    EXPECT_LE(tree.depth, VKP_LIGHT_TREE_MAX_DEPTH);
    EXPECT_EQ(checkSubtree(tree, 0), lights.size() - 1);
    EXPECT_EQ(tree.trails[7], VKP_NO_LIGHT);
    for (uint32_t light = 0; light < lights.size(); ++light)
        if (light != 7) {
            EXPECT_EQ(leafOfTrail(tree, tree.trails[light]), light);
        }
    EXPECT_TRUE(wavefront::buildLightTree(std::span(lights).first(1), power).nodes.empty());
}

struct ShadingPoint {
    const char* what;
    glm::vec3 p, n;  // world space; n = 0: no surface
};

// At points under, on and above the lamps, with and without a normal: 2^18
// walks' choices against lightTreePmf (chi-square, cells of expected count
// below 5 pooled, Sidak-corrected over the points at 1%; the walks that
// choose nothing against 1 less the probabilities' sum); and a light of
// probability 0 sends the point nothing (its light samples carry no
// radiance toward it, or arrive edge-on).
TEST(LightTreeSampling, ChoicesFollowTheProbabilitiesMisReads) {
    const wavefront::SceneTables tables = wavefront::buildSceneTables(lampField(6, true));
    wavefront::RenderSettings settings;
    settings.lightSampling = wavefront::LightSampling::Tree;
    const shared::SceneInfo info = wavefront::renderSceneInfo(tables, settings);
    ASSERT_EQ(info.treeLights, tables.lights.size());
    const shared::PathTracerView view(tables, info);
    const ShadingPoint points[] = {
        {"floor under a lamp", {-1.5f, 0.0f, -1.5f}, {0, 1, 0}},
        {"floor in the middle", {0.1f, 0.0f, 0.2f}, {0, 1, 0}},
        {"a wall facing +x", {-1.9f, 0.4f, 0.0f}, {1, 0, 0}},
        {"just under the lamps, no surface", {0.3f, 0.25f, -0.4f}, {0, 0, 0}},
        {"on a lamp's back", {-1.5f, 0.3f, -1.5f}, {0, 1, 0}},
        {"high above the lamps", {0.0f, 2.5f, 0.0f}, {0, 1, 0}}};
    const double alpha = test::sidakAlpha(0.01, std::size(points));
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (const ShadingPoint& point : points) {
        SCOPED_TRACE(point.what);
        const glm::vec3 p = point.p - glm::vec3(tables.worldOrigin);
        const glm::vec3 n = point.n == glm::vec3(0.0f) ? point.n : view.lightChoiceNormal(point.n);
        // One cell per light, and the last for walks that end where both
        // children are out of reach (their parent's wider bounds were not).
        std::vector<double> expected(info.treeLights + 1), observed(info.treeLights + 1, 0.0);
        double total = 0;
        constexpr int WALKS = 1 << 18;
        for (uint32_t light = 0; light < info.treeLights; ++light) {
            expected[light] = double(view.lightTreePmf(p, n, light)) * WALKS;
            total += expected[light] / WALKS;
        }
        EXPECT_LE(total, 1.0 + 1e-5);
        expected.back() = std::max(0.0, 1.0 - total) * WALKS;
        for (int i = 0; i < WALKS; ++i) {
            const auto s = view.sampleLightTree(p, n, uniform(rng));
            observed[s.light == VKP_NO_LIGHT ? info.treeLights : s.light] += 1;
            if (s.light == VKP_NO_LIGHT) continue;
            if (i < 4096) {
                EXPECT_EQ(s.pmf, view.lightTreePmf(p, n, s.light));
            }
        }
        const test::ChiSquareResult chi = test::chiSquareTest(observed, expected);
        EXPECT_GT(chi.pValue, alpha) << "chi2 " << chi.statistic << " dof " << chi.degreesOfFreedom;
        int unreachable = 0;
        for (uint32_t light = 0; light < info.treeLights; ++light) {
            if (expected[light] > 0) continue;
            ++unreachable;
            for (int i = 0; i < 64; ++i) {
                const shared::LightSample ls = shared::sampleLight(
                    tables.lights[light], p, glm::vec2(uniform(rng), uniform(rng)));
                const float incident =
                    point.n == glm::vec3(0.0f) ? 1.0f : glm::dot(point.n, ls.direction);
                // (an area light's point in p's plane, to the float rounding of p)
                const bool edgeOn = ls.normal != glm::vec3(0.0f) &&
                                    std::abs(glm::dot(ls.normal, ls.direction)) < 1e-4f;
                EXPECT_TRUE(ls.radiance == glm::vec3(0.0f) || !(ls.pdf > 0.0f) || edgeOn ||
                            incident == 0.0f)
                    << "light " << light << " has probability 0 but reaches the point";
            }
        }
        // On or above the lamps, which face down, none of their 72 triangles reaches.
        if (point.p.y >= 0.3f) {
            EXPECT_GE(unreachable, 72);
        }
    }
}

// The tree's choice needs the lights' power and places only: the same scene
// keeps power sampling below LIGHT_TREE_MIN_LIGHTS lights, and the choice is
// a feature bit of the kernels only where the render makes it.
TEST(LightTreeSampling, AutoChoosesTheTreeForManyLightsOnly) {
    wavefront::RenderSettings settings;
    const wavefront::SceneTables many = wavefront::buildSceneTables(lampField(4));
    const wavefront::SceneTables few = wavefront::buildSceneTables(lampField(1, true));
    ASSERT_LT(few.lightTree.trails.size(), wavefront::LIGHT_TREE_MIN_LIGHTS);
    ASSERT_FALSE(few.lightTree.nodes.empty());
    const auto features = [](const wavefront::SceneTables& t, const wavefront::RenderSettings& s) {
        return wavefront::renderFeatures(t, wavefront::renderSceneInfo(t, s));
    };
    EXPECT_TRUE(features(many, settings) & VKP_FEATURE_LIGHT_TREE);
    EXPECT_FALSE(features(few, settings) & VKP_FEATURE_LIGHT_TREE);
    settings.lightSampling = wavefront::LightSampling::Tree;
    EXPECT_TRUE(features(few, settings) & VKP_FEATURE_LIGHT_TREE);
    settings.lightSampling = wavefront::LightSampling::Power;
    EXPECT_FALSE(features(many, settings) & VKP_FEATURE_LIGHT_TREE);
    EXPECT_EQ(wavefront::renderSceneInfo(many, settings).treeLights, 0u);
}

// The lamp field with the lights at infinity, 48x48 at 256 spp, depth 3:
// the tree's image in the megakernel, the wavefront and the CPU reference
// against power sampling's, every 8x8 block z-tested (Sidak-corrected over
// the 36 blocks and the 3 comparisons at 1%; the variance of each pixel's
// mean from its own samples). And the tree's error is the smaller: on this
// field its mean variance is below power sampling's.
TEST(LightTreeRender, EstimatesThePowerSampledImageEverywhere) {
    const scene::Scene s = lampField(8);
    wavefront::RenderSettings settings = test::squareSettings(48, 256, 3, 5);
    settings.lightSampling = wavefront::LightSampling::Power;
    const wavefront::RenderResult power = test::renderGpu(s, settings);
    settings.lightSampling = wavefront::LightSampling::Tree;
    const double alpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / 3.0);
    double treeVariance = 0, powerVariance = 0;
    for (const auto& [what, kernel] : {std::pair{"megakernel", wavefront::KernelForm::Megakernel},
                                       std::pair{"wavefront", wavefront::KernelForm::Wavefront}}) {
        SCOPED_TRACE(what);
        settings.kernel = kernel;
        settings.seed = kernel == wavefront::KernelForm::Megakernel ? 6 : 7;
        const wavefront::RenderResult tree = test::renderGpu(s, settings);
        const image::BlockComparison z = image::compareBlocks(
            tree.image, tree.varianceOfMean, power.image, power.varianceOfMean, 8, alpha);
        EXPECT_EQ(z.rejected, 0u) << "worst |z| " << z.worstZ;
        if (kernel == wavefront::KernelForm::Megakernel) {
            for (size_t i = 0; i < tree.varianceOfMean.pixels.size(); ++i) {
                treeVariance += double(tree.varianceOfMean.pixels[i].y);
                powerVariance += double(power.varianceOfMean.pixels[i].y);
            }
        }
    }
    EXPECT_LT(treeVariance, 0.5 * powerVariance);
    settings.seed = 8;
    wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    const wavefront::RenderResult cpu = reference::ReferenceRenderer(tables, settings).render();
    const image::BlockComparison z = image::compareBlocks(
        cpu.image, cpu.varianceOfMean, power.image, power.varianceOfMean, 8, alpha);
    EXPECT_EQ(z.rejected, 0u) << "CPU reference: worst |z| " << z.worstZ;

    // The test's power: two lamps' trails swapped (in opposite corners), so
    // that what a BSDF sample's MIS weight reads is not what the light
    // sample chose, and the image is no longer the same.
    std::swap(tables.lightTree.trails.front(), tables.lightTree.trails[126]);
    const wavefront::RenderResult broken = reference::ReferenceRenderer(tables, settings).render();
    EXPECT_GT(image::compareBlocks(broken.image, broken.varianceOfMean, power.image,
                                   power.varianceOfMean, 8, alpha)
                  .rejected,
              0u);
}

// Scenes past a binding read the tree's nodes and trails by address
// (stages/lib/scene_access.glsl): the same image bits as bound.
TEST(LightTreeRender, ReadByAddressGivesTheSameImage) {
    const scene::Scene s = lampField(8);
    wavefront::RenderSettings settings = test::squareSettings(32, 16, 3, 9);
    settings.lightSampling = wavefront::LightSampling::Tree;
    const wavefront::RenderResult bound = test::renderGpu(s, settings);
    const test::BindingLimit limit(4096);
    const wavefront::RenderResult byAddress = test::renderGpu(s, settings);
    ASSERT_EQ(bound.image.pixels.size(), byAddress.image.pixels.size());
    for (size_t i = 0; i < bound.image.pixels.size(); ++i)
        ASSERT_EQ(bound.image.pixels[i], byAddress.image.pixels[i]) << "pixel " << i;
}

}  // namespace
