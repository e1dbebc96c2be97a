// The Sobol' sampler (--sampler sobol) in whole renders: it stays unbiased on
// scenes whose answer is known exactly, and at equal samples per pixel its
// error against that answer is lower than the independent sampler's.
#include <gtest/gtest.h>

#include <cmath>

#include "image/statistics.h"
#include "scene/scene.h"
#include "support/gpu_render.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;
using wavefront::SamplerKind;

// A diffuse sphere of albedo `albedo` in a constant white environment: every
// pixel that sees the sphere is `albedo` at depth >= 1 (a convex sphere
// reflects once and its light escapes), found by MIS of environment and BSDF
// samples.
scene::Scene sphereInFurnace(float albedo) {
    return test::sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(albedo));
}

// Inside a closed emissive sphere of albedo rho and emitted radiance 1: the
// radiance after at most m bounces is sum_{k=0..m} rho^k, in every pixel.
scene::Scene insideEmitter(float albedo) {
    scene::Scene s;
    scene::Material m;
    m.reflectance = glm::vec3(albedo);
    m.emission = glm::vec3(1.0f);
    s.materials.push_back(m);
    s.spheres.push_back({"room", glm::vec3(0.0f, 0.5f, 0.0f), 3.0f, 0});
    s.camera.position = {0.0f, 0.0f, 0.0f};
    s.camera.target = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = 60.0f;
    return s;
}

double geometricSeries(double rho, uint32_t depth) {
    double sum = 0;
    for (uint32_t k = 0; k <= depth; ++k) sum += std::pow(rho, double(k));
    return sum;
}

using test::render;

// Pixels whose whole footprint sees the sphere of sphereInFurnace.
bool onSphere(uint32_t x, uint32_t y, uint32_t size) {
    const double cx = (x + 0.5) / size * 2 - 1, cy = (y + 0.5) / size * 2 - 1;
    return cx * cx + cy * cy < 0.6 * 0.6;
}

// ---- unbiased -----------------------------------------------------------------------

// A bound of 5 standard errors, as in render_test.cpp. The standard error
// comes from the variance AOV, the samples' variance / n, which for
// stratified samples overstates the error of their mean: the test is
// conservative, and still fails on a bias of a few standard errors.
constexpr double Z_BOUND = 5.0;

void expectRegionMean(const wavefront::RenderResult& r, bool sphereOnly, double expected) {
    const auto region = image::regionMean(r.image, r.varianceOfMean, [&](uint32_t x, uint32_t y) {
        return !sphereOnly || onSphere(x, y, r.image.width);
    });
    ASSERT_GT(region.pixels, 100u);
    EXPECT_NEAR(region.mean, expected, Z_BOUND * region.standardError + 1e-5 * expected)
        << "standard error " << region.standardError;
    EXPECT_EQ(r.nonFiniteSamples, 0u);
}

TEST(SobolRender, WhiteFurnaceSphereIsInvisible) {
    for (uint32_t lightSamples : {1u, 3u}) {
        SCOPED_TRACE(lightSamples);
        const auto r =
            render(sphereInFurnace(1.0f), 16, 8, 48, 1, lightSamples, SamplerKind::Sobol);
        expectRegionMean(r, false, 1.0);
    }
}

TEST(SobolRender, GreySphereReflectsItsAlbedo) {
    expectRegionMean(render(sphereInFurnace(0.5f), 16, 3, 48, 1, 1, SamplerKind::Sobol), true, 0.5);
}

// Depth 5 with Russian roulette from bounce 4: every pair of a bounce in use.
TEST(SobolRender, InsideAnEmitterGivesTheGeometricSeries) {
    for (uint32_t depth : {1u, 5u}) {
        SCOPED_TRACE(depth);
        expectRegionMean(render(insideEmitter(0.9f), 8, depth, 32, 1, 1, SamplerKind::Sobol), false,
                         geometricSeries(0.9, depth));
    }
}

// ---- lower error --------------------------------------------------------------------

// Mean squared error of the sphere's pixels against the exact value.
double sphereSquaredError(const wavefront::RenderResult& r, double exact) {
    double sum = 0;
    uint32_t n = 0;
    for (uint32_t y = 0; y < r.image.height; ++y)
        for (uint32_t x = 0; x < r.image.width; ++x)
            if (onSphere(x, y, r.image.width)) {
                const double d = r.image.at(x, y).x - exact;
                sum += d * d;
                ++n;
            }
    return sum / n;
}

// The grey sphere at 64 spp, 32x32 pixels: the independent sampler's squared
// error over Sobol's, measured for seeds 1..6, was 10.6 to 12.5 (1.8 to 1.9
// at 4 spp, 3.2 to 4.4 at 16). The test asks for 4 summed over three seeds:
// 2.6x below the worst seed measured, and far from what two renders with the
// same sampler reach by chance (the mean squared error of ~900 independent
// pixels varies by about 5%, so their ratio stays within ~20% of 1).
constexpr uint32_t ERROR_SPP = 64;
constexpr double MIN_ERROR_RATIO = 4.0;

TEST(SobolRender, LowerErrorThanIndependentAtEqualSpp) {
    const scene::Scene s = sphereInFurnace(0.5f);
    double independent = 0, sobol = 0;
    for (uint32_t seed = 1; seed <= 3; ++seed) {
        independent +=
            sphereSquaredError(render(s, ERROR_SPP, 3, 32, seed, 1, SamplerKind::Independent), 0.5);
        sobol += sphereSquaredError(render(s, ERROR_SPP, 3, 32, seed, 1, SamplerKind::Sobol), 0.5);
    }
    RecordProperty("errorRatio", std::to_string(independent / sobol));
    EXPECT_GT(independent, MIN_ERROR_RATIO * sobol)
        << "independent " << independent << ", sobol " << sobol;
}

}  // namespace
