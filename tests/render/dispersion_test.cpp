// Dispersion (KHR_materials_dispersion, shared/spectral.h) in whole renders:
// a white furnace stays white in every channel (each path's wavelength
// weight averages 1 and glass loses no light), white light refracted past an
// edge splits into colours only where the glass disperses, and every
// execution of the path loop agrees (the wavefront keeps each path's
// wavelength in a buffer of its own, the megakernel and the CPU reference in
// the path's state). Bounds: 5 standard errors from the render's own
// variance AOV (false alarm 6e-7 per check).
#include <gtest/gtest.h>

#include <cmath>

#include "scene/scene.h"
#include "support/executions.h"
#include "support/gpu_render.h"
#include "support/test_scenes.h"

namespace {

using namespace vkpath;

constexpr double Z_BOUND = 5.0;

// Clear glass of index 1.5 with `dispersion` (20 / Abbe number), solid.
scene::Material flint(float dispersion) {
    scene::Material m;
    m.kind = scene::MaterialKind::Dielectric;
    m.reflectance = glm::vec3(1.0f);
    m.transmittance = glm::vec3(1.0f);
    m.ior = 1.5f;
    m.dispersion = dispersion;
    return m;
}

// The unit sphere of `glass` in a white sky, seen from (0, 0, 4): the
// furnace. Pixels within 0.6 of the film's half-width of its centre see the
// sphere.
TEST(DispersionRender, AFurnaceStaysWhiteInEveryChannel) {
    scene::Scene s = test::sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(1.0f));
    s.materials[0] = flint(2.0f);
    const uint32_t size = 48;
    const auto r = test::renderGpu(s, test::squareSettings(size, 64, 24));
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    for (int c = 0; c < 3; ++c) {
        double sum = 0, variance = 0;
        uint64_t pixels = 0;
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) {
                const double cx = (x + 0.5) / size * 2 - 1, cy = (y + 0.5) / size * 2 - 1;
                if (cx * cx + cy * cy >= 0.36) continue;
                const size_t i = size_t(y) * size + x;
                sum += r.image.pixels[i][c];
                variance += r.varianceOfMean.pixels[i][c];
                ++pixels;
            }
        const double mean = sum / double(pixels),
                     standardError = std::sqrt(variance) / double(pixels);
        EXPECT_NEAR(mean, 1.0, Z_BOUND * standardError) << "channel " << c;
        EXPECT_GT(standardError, 0.0) << "no wavelength weight varied";
    }
}

// A glass ball in front of a white wall's edge (the wall covers x < -1
// behind it; black elsewhere): without dispersion every pixel is grey
// (R = B bit for bit); with an Abbe number of 10 the edge seen through the
// ball's side (a crescent, blue on its inner edge and red on its outer)
// splits into colours: red and blue apart by more than 5 standard errors in
// at least 5 pixels (were the colours equal in expectation, the chance of
// even one of the 2304 pixels past 5 standard errors would be 1.3e-3; 15
// pass at 256 spp).
scene::Scene edgeBehindABall(float dispersion) {
    scene::Scene s;
    s.materials.push_back(flint(dispersion));
    s.spheres.push_back({"ball", glm::vec3(0.0f), 0.8f, 0});
    scene::Material wall;
    wall.emission = glm::vec3(1.0f);
    s.materials.push_back(wall);
    scene::Mesh half;
    half.positions = {{-6, 6, -3}, {-6, -6, -3}, {-1, -6, -3}, {-1, 6, -3}};
    half.triangles = {{0, 1, 2}, {0, 2, 3}};
    half.material = 1;
    s.meshes.push_back(half);
    s.camera.position = {0.0f, 0.0f, 4.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 30.0f;
    return s;
}

size_t colouredPixels(const wavefront::RenderResult& r) {
    size_t coloured = 0;
    for (size_t i = 0; i < r.image.pixels.size(); ++i) {
        const glm::vec3 p = r.image.pixels[i], v = r.varianceOfMean.pixels[i];
        coloured += std::abs(p.x - p.z) > Z_BOUND * std::sqrt(double(v.x) + v.z);
    }
    return coloured;
}

TEST(DispersionRender, SplitsWhiteLightOnlyWhereTheGlassDisperses) {
    const auto settings = test::squareSettings(48, 256, 8);
    const auto grey = test::renderGpu(edgeBehindABall(0.0f), settings);
    for (const glm::vec3& p : grey.image.pixels) ASSERT_EQ(p.x, p.z);
    const auto split = test::renderGpu(edgeBehindABall(2.0f), settings);
    EXPECT_GE(colouredPixels(split), 5u);
}

// Wavefront, megakernel and general kernel the same bits, the CPU reference
// the same image (block z-test), on the ball before the edge.
TEST(DispersionRender, EveryExecutionAgrees) {
    test::expectEveryExecutionAgrees(edgeBehindABall(1.0f), test::squareSettings(24, 16, 6));
}

}  // namespace
