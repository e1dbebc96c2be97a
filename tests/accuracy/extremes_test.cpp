// Numerical stability at the extremes, through the whole renderer:
//   - scale: the bundled Cornell box scaled by 1e-4 and 1e4 and moved 1e5 away
//     renders the same image (block z-tests against the unscaled render);
//   - depth: -m 1000 with Russian roulette terminates and matches -m 64;
//   - non-finite: zero-area triangles, zero-radius spheres and a 1e38 emitter
//     give finite pixels, with the overflowing samples dropped and counted.
// Every check of two renders uses 8x8 blocks with Welch z-tests from the
// variance AOV at a 1% false-alarm rate, Sidak-corrected over the blocks.
#include <gtest/gtest.h>

#include <cmath>

#include "image/statistics.h"
#include "reference/reference_renderer.h"
#include "scene/environment.h"
#include "scene/environment_table.h"
#include "scene/load.h"
#include "support/gpu_render.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

using test::render;

// p -> scale * p + offset for everything with a position; radiances stay, a
// point light's intensity grows with scale^2 so its irradiance stays.
scene::Scene transformed(scene::Scene s, float scale, glm::vec3 offset) {
    auto move = [&](glm::vec3 p) { return scale * p + offset; };
    for (auto& mesh : s.meshes)
        for (auto& p : mesh.positions) p = move(p);
    for (auto& sphere : s.spheres) {
        sphere.center = move(sphere.center);
        sphere.radius *= scale;
    }
    for (auto& light : s.pointLights) {
        light.position = move(light.position);
        light.intensity *= scale * scale;
    }
    s.camera.position = move(s.camera.position);
    s.camera.target = move(s.camera.target);
    return s;
}

void expectSameImage(const wavefront::RenderResult& a, const wavefront::RenderResult& b) {
    EXPECT_EQ(a.nonFiniteSamples, 0u);
    EXPECT_EQ(b.nonFiniteSamples, 0u);
    const auto c =
        image::compareBlocks(a.image, a.varianceOfMean, b.image, b.varianceOfMean, 8, 0.01);
    EXPECT_EQ(c.rejected, 0) << "worst z " << c.worstZ << " over " << c.blocks << " blocks";
}

class SceneScale : public testing::TestWithParam<std::pair<float, float>> {};

// A translation by 1e5 rounds the box's vertices to the float grid there
// (8 mm at 1e5, on a box of 0.55 m): the scene itself changes. The reference
// for that case is the rounded scene moved back to the origin, which is exact
// (x - 1e5 for floats near 1e5 has no rounding error), so the two renders
// differ only in where the renderer computes: that is what this tests.
TEST_P(SceneScale, CornellBoxLooksTheSame) {
    const auto [scale, offset] = GetParam();
    const glm::vec3 shift(offset, -0.5f * offset, 0.25f * offset);
    const scene::Scene loaded = scene::loadScene(test::sourcePath("assets/cornell_box.gltf"));
    const scene::Scene moved = transformed(loaded, scale, shift);
    const scene::Scene base = offset != 0 ? transformed(moved, 1.0f, -shift) : loaded;
    const auto reference = render(base, 16, 6, 40, 1);
    const auto far = render(moved, 16, 6, 40, 2);
    expectSameImage(reference, far);
}

INSTANTIATE_TEST_SUITE_P(Extremes, SceneScale,
                         testing::Values(std::pair{1e-4f, 0.0f}, std::pair{1e4f, 0.0f},
                                         std::pair{1.0f, 1e5f}),
                         [](const testing::TestParamInfo<std::pair<float, float>>& param) {
                             return param.param.second != 0
                                        ? std::string("Translated1e5")
                                        : (param.param.first < 1 ? std::string("Scaled1em4")
                                                                 : std::string("Scaled1e4"));
                         });

// The scale test has power: a box with a dimmer lamp is told apart.
TEST(SceneScale, DetectsADifferentScene) {
    const scene::Scene base = scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    scene::Scene dimmer = base;
    for (auto& m : dimmer.materials) m.emission *= 0.9f;
    const auto a = render(base, 16, 6, 40, 1), b = render(dimmer, 16, 6, 40, 2);
    EXPECT_GT(image::compareBlocks(a.image, a.varianceOfMean, b.image, b.varianceOfMean, 8, 0.01)
                  .rejected,
              0);
}

// Russian roulette ends paths long before 1000 bounces, and what it adds
// beyond 64 bounces is below the noise: the two agree statistically.
TEST(Depth, ThousandBouncesMatchSixtyFour) {
    const scene::Scene box = scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    const auto deep = render(box, 16, 1000, 32, 1);
    const auto shallow = render(box, 16, 64, 32, 2);
    expectSameImage(deep, shallow);
}

// Degenerate geometry is never hit and a 1e38 emitter overflows float: no
// pixel may be NaN or infinite, and the overflowing samples are counted.
TEST(NonFinite, DegenerateGeometryAndHugeEmissionStayFinite) {
    scene::Scene s = scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    scene::Material huge;
    huge.emission = glm::vec3(1e38f);
    s.materials.push_back(huge);
    const uint32_t hugeMaterial = uint32_t(s.materials.size() - 1);
    const glm::vec3 c = s.camera.target;
    s.spheres.push_back({"sun", c + glm::vec3(0.0f, 0.1f, 0.0f), 0.05f, hugeMaterial});
    s.spheres.push_back({"point", c, 0.0f, 0});  // zero radius
    scene::Mesh flat;                            // zero-area triangles
    flat.positions = {c, c + glm::vec3(0.1f, 0, 0), c + glm::vec3(0.2f, 0, 0), c};
    flat.triangles = {{0, 1, 2}, {0, 3, 1}};
    flat.material = hugeMaterial;
    s.meshes.push_back(flat);
    const auto r = render(s, 4, 4, 24, 1);
    for (const glm::vec3& p : r.image.pixels)
        for (int i = 0; i < 3; ++i) ASSERT_TRUE(std::isfinite(p[i]));
    EXPECT_GT(r.nonFiniteSamples, 0u);
    EXPECT_EQ(r.rejectedLightSamples, 0u)
        << "no light here has a pdf of 0: the degenerate ones are not lights";
}

// Lights whose pdf is 0 from where they are sampled: two emissive quads in
// the floor's plane, just outside the box's side walls, facing down. The
// light sampler picks each as often as the lamp (same power), and from the
// floor they are seen exactly edge-on (cosine 0: pdf 0, or within rounding
// of it), from everything above at their back. They light nothing, so the
// image must equal the plain box's (block z-test), and the pdf-0 samples must
// be rejected where they arise, in the light-sampling code: not one may reach
// the film as a NaN (0 / 0) to be dropped there, so the non-finite count is 0.
TEST(NonFinite, LightsWithPdfZeroAreRejectedBeforeTheFilm) {
    const scene::Scene box = scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    scene::Scene s = box;
    double lampPower = 0;
    for (const auto& mesh : box.meshes)
        if (box.materials[mesh.material].emissive())
            for (const auto& t : mesh.triangles)
                lampPower +=
                    0.5 *
                    glm::length(glm::cross(glm::dvec3(mesh.positions[t.y] - mesh.positions[t.x]),
                                           glm::dvec3(mesh.positions[t.z] - mesh.positions[t.x]))) *
                    scene::luminance(box.materials[mesh.material].emission);
    ASSERT_GT(lampPower, 0);
    scene::Material edgeOn;
    edgeOn.name = "edge-on lamp";
    const float side = 0.2f, depth = 0.5f;  // each quad 0.2 x 0.5 m
    edgeOn.emission = glm::vec3(float(lampPower / (side * depth)));
    s.materials.push_back(edgeOn);
    for (float x0 : {0.3f, -0.3f - side}) {
        scene::Mesh quad;  // y = 0, the floor's plane; wound so the normal is -y
        quad.positions = {{x0, 0, -0.05f},
                          {x0 + side, 0, -0.05f},
                          {x0 + side, 0, -0.05f - depth},
                          {x0, 0, -0.05f - depth}};
        quad.triangles = {{0, 2, 1}, {0, 3, 2}};
        quad.material = uint32_t(s.materials.size() - 1);
        const glm::vec3 n = glm::cross(quad.positions[2] - quad.positions[0],
                                       quad.positions[1] - quad.positions[0]);
        ASSERT_LT(n.y, 0.0f);
        s.meshes.push_back(quad);
    }
    const auto withEdgeOn = render(s, 16, 6, 40, 1);
    const auto plain = render(box, 16, 6, 40, 2);
    for (const glm::vec3& p : withEdgeOn.image.pixels)
        for (int i = 0; i < 3; ++i) ASSERT_TRUE(std::isfinite(p[i]));
    EXPECT_EQ(withEdgeOn.nonFiniteSamples, 0u);
    // The plain box rejects some too: its lamp lies in the ceiling's plane.
    // Each quad is picked as often as the lamp, and from every floor point it is edge-on.
    EXPECT_GT(withEdgeOn.rejectedLightSamples, 2 * plain.rejectedLightSamples + 1000)
        << "the floor sees the quads edge-on: pdf 0";
    expectSameImage(withEdgeOn, plain);
    // The CPU reference follows the same paths (same seed), up to the few
    // that float rounding sends elsewhere (SameSeed: at most 3% of pixels
    // differ; measured 8 of 7488 rejections, 0.1%).
    wavefront::RenderSettings settings;
    settings.width = settings.height = 40;
    settings.samplesPerPixel = 16;
    settings.maxDepth = 6;
    settings.seed = 1;
    const double cpu =
        double(reference::ReferenceRenderer(s, settings).render().rejectedLightSamples);
    EXPECT_NEAR(cpu, double(withEdgeOn.rejectedLightSamples), 0.03 * cpu);
}

}  // namespace

namespace {

// A blinding sky: fireflies are counted without --clamp, and with a clamp no
// sample (so no pixel mean) exceeds it. The clamp is biased by design: the
// clamped image is darker than the unclamped one.
TEST(Brightness, FirefliesAreCountedAndClampedOnlyOnRequest) {
    scene::Scene s = scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    for (auto& m : s.materials) m.emission *= 1e5f;
    wavefront::RenderSettings settings;
    settings.width = settings.height = 24;
    settings.samplesPerPixel = 4;
    settings.maxDepth = 4;
    wavefront::GpuRenderer free(test::context(), s, settings);
    const auto unclamped = free.render();
    EXPECT_GT(unclamped.fireflySamples, 0u);
    EXPECT_EQ(unclamped.nonFiniteSamples, 0u);
    settings.clampRadiance = 2.0f;
    wavefront::GpuRenderer clamped(test::context(), s, settings);
    const auto c = clamped.render();
    double sumClamped = 0, sumFree = 0;
    for (size_t i = 0; i < c.image.pixels.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            ASSERT_LE(c.image.pixels[i][k], 2.0f * (1 + 1e-6f));
            sumClamped += c.image.pixels[i][k];
            sumFree += unclamped.image.pixels[i][k];
        }
    EXPECT_LT(sumClamped, sumFree);
}

// The 1e5 sun over a dim room: radiance from 1e-6 to 1e6 in one scene. The
// bundled sky (assets/sky.hdr: a 0.5 degree sun at ~1e5 times the sky) at
// strength 10 shines through the Cornell box, its ceiling removed, onto walls
// lit otherwise only by the lamp turned down to ~1e-6. Criteria: every pixel
// finite and no sample dropped as non-finite; every texel of the sky with
// radiance keeps a nonzero sampling probability (the proportionality itself
// is EnvironmentSampling.SkyWithSunAtExtremeRatios); fireflies (a sample
// adding more than 1 to its pixel) are counted and reported, and left in the
// image: without --clamp some pixel stays above the clamp value; with it none
// does. The clamp is the only thing that limits them (biased, so opt-in).
TEST(Brightness, SunOverADimRoom) {
    scene::Scene s = scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
    float top = 0;
    for (const auto& mesh : s.meshes)
        for (const glm::vec3& p : mesh.positions) top = std::max(top, p.y);
    size_t removed = 0;
    for (auto& mesh : s.meshes) {
        std::erase_if(mesh.triangles, [&](const glm::uvec3& t) {
            const bool ceiling = mesh.positions[t.x].y == top && mesh.positions[t.y].y == top &&
                                 mesh.positions[t.z].y == top;
            removed += ceiling;
            return ceiling;
        });
    }
    ASSERT_GT(removed, 0u) << "no ceiling found";
    for (auto& m : s.materials) m.emission *= 1e-6f / 17.0f;  // the lamp: 17 W/(m^2 sr) -> 1e-6
    scene::Environment sky;
    sky.map = scene::loadEnvironmentMap(test::sourcePath("assets/sky.hdr"));
    sky.strength = 10.0f;
    s.environment = sky;
    const auto table = scene::buildEnvironmentTable(*sky.map);
    float brightest = 0;
    for (size_t i = 0; i < sky.map->pixels.size(); ++i) {
        brightest = std::max(brightest, float(scene::luminance(sky.map->pixels[i])));
        if (scene::luminance(sky.map->pixels[i]) > 0) {
            ASSERT_GT(table.entries[i].probability, 0.0f) << i;
        }
    }
    EXPECT_GT(brightest * sky.strength, 1e5f) << "the sun should be ~1e6 at strength 10";

    wavefront::RenderSettings settings;
    settings.width = settings.height = 24;
    settings.samplesPerPixel = 16;
    settings.maxDepth = 4;
    wavefront::GpuRenderer free(test::context(), s, settings);
    const auto unclamped = free.render();
    EXPECT_EQ(unclamped.nonFiniteSamples, 0u);
    EXPECT_GT(unclamped.fireflySamples, 0u);
    float largest = 0;
    for (const glm::vec3& p : unclamped.image.pixels)
        for (int k = 0; k < 3; ++k) {
            ASSERT_TRUE(std::isfinite(p[k]));
            largest = std::max(largest, p[k]);
        }
    constexpr float CLAMP = 4.0f;
    EXPECT_GT(largest, CLAMP) << "fireflies are not clamped unless asked";
    settings.clampRadiance = CLAMP;
    wavefront::GpuRenderer clamped(test::context(), s, settings);
    const auto c = clamped.render();
    EXPECT_GT(c.fireflySamples, 0u);
    for (const glm::vec3& p : c.image.pixels)
        for (int k = 0; k < 3; ++k) ASSERT_LE(p[k], CLAMP * (1 + 1e-6f));
}

}  // namespace
