// Participating media (shared/medium.h, shared/path/media.h): the fog and
// the scattering inside transmitting bodies, checked where the answer is
// known: Beer-Lambert exactly, a furnace, single scattering against its
// line integral, and the three executions against each other. Bounds: 5
// standard errors from the render's own variance AOV (a false alarm of
// 6e-7 per check), block comparisons at a 1% family-wise rate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "image/statistics.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "scene/scene.h"
#include "shared/features.h"
#include "shared/phase.h"
#include "support/executions.h"
#include "support/gpu_render.h"
#include "support/test_scenes.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"

namespace {

using namespace vkpath;

constexpr double Z_BOUND = 5.0;

// The camera at the centre of an emissive sphere of radius 2 (radiance 1,
// black), in a fog that only absorbs: every ray crosses 2 m of it, so every
// pixel is exp(-2 sigma_a), exactly but for the rounding of the hit distance
// (a few float ulps) and of exp. Nothing scatters, so the estimate has no
// noise at all, in each of the three executions.
TEST(Media, FogThatOnlyAbsorbsIsBeerLambert) {
    scene::Scene s = test::cameraInsideALampSphere(2.0f);
    s.fog.absorption = {0.1f, 0.5f, 1.5f};
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    EXPECT_TRUE(wavefront::sceneFeatures(tables) & VKP_FEATURE_MEDIA);

    wavefront::RenderSettings settings = test::squareSettings(16, 4, 2);
    settings.kernel = wavefront::KernelForm::Wavefront;
    const auto wavefrontResult = test::renderGpu(s, settings);
    settings.kernel = wavefront::KernelForm::Megakernel;
    const auto megakernel = test::renderGpu(s, settings);
    const auto cpu = test::renderCpu(s, settings);
    EXPECT_TRUE(test::sameBits(wavefrontResult.image, megakernel.image));
    for (const auto* r : {&megakernel, &cpu})
        for (const glm::vec3& p : r->image.pixels)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p[c], std::exp(-2.0 * s.fog.absorption[c]),
                            1e-5 * std::exp(-2.0 * s.fog.absorption[c]))
                    << c;
}

// A white furnace with a medium in it: a sphere of index 1 (its surface
// neither reflects nor bends) holding a medium that scatters and does not
// absorb, in a sky of radiance 1. Light that enters leaves after any number
// of scattering events, so every pixel is 1: its mean over the sphere within
// 5 standard errors of 1. Optical radius 2 to 6 (the colour's channels), a
// forward and a backward phase function; 200 bounces leave a path that is
// still inside with a chance far below the test's resolution. The same
// sphere with a medium of albedo 0.95 is darker by more than the bound (the
// test's power).
TEST(Media, ScatteringInsideAnIndexMatchedSphereIsAFurnace) {
    struct Case {
        const char* name;
        glm::vec3 attenuation;
        float albedo;
        float g;
        bool conserves;
    };
    const Case cases[] = {
        {"grey, g 0.6", glm::vec3(2.0f), 1.0f, 0.6f, true},
        {"chromatic, g -0.4", {2.0f, 4.0f, 6.0f}, 1.0f, -0.4f, true},
        {"absorbing (albedo 0.95)", glm::vec3(2.0f), 0.95f, 0.0f, false},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        scene::Scene s =
            test::sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(1.0f), 1.0f);
        s.materials[0].attenuation = c.attenuation;
        s.materials[0].scatteringAlbedo = glm::vec3(c.albedo);
        s.materials[0].scatterAnisotropy = c.g;
        const auto r = test::renderGpu(s, test::squareSettings(32, 64, 200, 5));
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        const auto sphere =
            image::regionMean(r.image, r.varianceOfMean, [](uint32_t x, uint32_t y) {
                const double cx = (x + 0.5) / 32 * 2 - 1, cy = (y + 0.5) / 32 * 2 - 1;
                return cx * cx + cy * cy < 0.36;  // within the sphere's silhouette (0.73)
            });
        ASSERT_GT(sphere.pixels, 100u);
        std::printf("  %s: sphere %.5f +- %.5f\n", c.name, sphere.mean, sphere.standardError);
        if (c.conserves)
            // (+1e-6: a grey medium that only scatters gives every path weight 1,
            // so the mean is 1 up to float rounding with no noise at all)
            EXPECT_NEAR(sphere.mean, 1.0, Z_BOUND * sphere.standardError + 1e-6);
        else
            EXPECT_LT(sphere.mean, 1.0 - Z_BOUND * sphere.standardError);
    }
}

// Single scattering of a point light in an infinite fog, against its line
// integral. The camera looks along -z from (0, 1, 4), the light (intensity
// I) at the origin; with one bounce a path scatters once and takes its one
// light sample (a point light's: weight 1), so a camera ray of direction
// w sees
//
//   L(w) = int_0^inf sigma_s exp(-sigma_t t) p(-w . l) I exp(-sigma_t d) / d^2 dt,
//
// d the distance from the scattering point x = o + t w to the light and l the
// unit direction from x to it. The film's mean is L's mean over the film
// plane (jittered pixels cover it uniformly): midpoint rule over 32 x 32
// positions in double, each line integral by Simpson's rule over 40 optical
// depths (the tail beyond is below exp(-40)). The film's mean within 5
// standard errors + 2e-3 relative (the quadrature's error, measured by halving
// both grids: under 3e-4).
TEST(Media, SingleScatteringOfAPointLightIsItsLineIntegral) {
    const glm::dvec3 scattering(0.3, 0.2, 0.1), absorption(0.1, 0.05, 0.3);
    const double g = 0.4, intensity = 10.0, xfov = 10.0;
    scene::Scene s;
    scene::Material black;
    black.reflectance = glm::vec3(0.0f);
    s.materials.push_back(black);
    // (a primitive for the tree, out of sight behind the camera)
    s.spheres.push_back({"speck", glm::vec3(0.0f, 1.0f, 50.0f), 0.01f, 0});
    s.pointLights.push_back({glm::vec3(0.0f), glm::vec3(float(intensity)), 0.0f});
    s.camera.position = {0.0f, 1.0f, 4.0f};
    s.camera.target = {0.0f, 1.0f, 0.0f};
    s.camera.xfovDegrees = float(xfov);
    s.fog.scattering = glm::vec3(scattering);
    s.fog.absorption = glm::vec3(absorption);
    s.fog.anisotropy = float(g);

    const glm::dvec3 origin(0, 1, 4), light(0, 0, 0);
    const double tanHalf = std::tan(xfov * 0.5 * M_PI / 180.0);
    auto radiance = [&](const glm::dvec3& w, int c) {
        const double sigmaT = scattering[c] + absorption[c];
        const double tEnd = 40.0 / sigmaT;
        const int steps = 4000;
        const double h = tEnd / steps;
        double sum = 0;
        for (int i = 0; i <= steps; ++i) {
            const double t = i * h;
            const glm::dvec3 toLight = light - (origin + t * w);
            const double d = glm::length(toLight);
            const double phase =
                shared::henyeyGreenstein(float(glm::dot(-w, toLight / d)), float(g));
            const double f =
                scattering[c] * std::exp(-sigmaT * (t + d)) * phase * intensity / (d * d);
            sum += f * (i == 0 || i == steps ? 1 : i % 2 ? 4 : 2);
        }
        return sum * h / 3;
    };
    glm::dvec3 expected(0.0);
    const int grid = 32;
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
            const double x = ((i + 0.5) / grid * 2 - 1) * tanHalf;
            const double y = ((j + 0.5) / grid * 2 - 1) * tanHalf;
            const glm::dvec3 w = glm::normalize(glm::dvec3(x, y, -1.0));
            for (int c = 0; c < 3; ++c) expected[c] += radiance(w, c) / (grid * grid);
        }

    wavefront::RenderSettings settings = test::squareSettings(16, 256, 1, 7);
    for (const bool cpu : {false, true}) {
        SCOPED_TRACE(cpu ? "CPU reference" : "GPU");
        const auto r = cpu ? test::renderCpu(s, settings) : test::renderGpu(s, settings);
        glm::dvec3 mean(0.0), variance(0.0);
        for (size_t p = 0; p < r.image.pixels.size(); ++p) {
            mean += glm::dvec3(r.image.pixels[p]);
            variance += glm::dvec3(r.varianceOfMean.pixels[p]);
        }
        const double n = double(r.image.pixels.size());
        mean /= n;
        for (int c = 0; c < 3; ++c) {
            const double standardError = std::sqrt(variance[c]) / n;
            std::printf("  channel %d: film %.6f +- %.6f, integral %.6f\n", c, mean[c],
                        standardError, expected[c]);
            EXPECT_NEAR(mean[c], expected[c], Z_BOUND * standardError + 2e-3 * expected[c]);
        }
    }
}

// A foggy Cornell box with a glass sphere full of a scattering medium: the
// two GPU kernel forms give the same bits, the general kernel too, and the
// CPU reference the same image (block z-tests).
TEST(Media, EveryExecutionRendersTheSameFoggyBox) {
    scene::Scene s = scene::loadScene(VKPATH_SOURCE_DIR "/assets/cornell_box.gltf");
    s.fog.scattering = glm::vec3(0.6f, 0.7f, 0.8f);
    s.fog.absorption = glm::vec3(0.1f);
    s.fog.anisotropy = 0.3f;
    bool glass = false;
    for (scene::Material& m : s.materials)
        if (m.kind == scene::MaterialKind::Dielectric) {
            m.attenuation = glm::vec3(8.0f, 12.0f, 16.0f);
            m.scatteringAlbedo = glm::vec3(0.9f);
            m.scatterAnisotropy = -0.2f;
            glass = true;
        }
    ASSERT_TRUE(glass);
    wavefront::RenderSettings settings = test::squareSettings(32, 64, 6, 11);
    test::expectEveryExecutionAgrees(s, settings);
}

// A scene without a medium compiles none of it, and glass that only absorbs
// keeps Beer-Lambert without the medium code (shared/path/absorption.h).
TEST(Media, OnlyAScatteringMediumOrFogSetsTheFeature) {
    scene::Scene s =
        test::sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(1.0f), 1.5f);
    auto features = [](const scene::Scene& scene) {
        return wavefront::sceneFeatures(wavefront::buildSceneTables(scene));
    };
    EXPECT_FALSE(features(s) & VKP_FEATURE_MEDIA);
    s.materials[0].attenuation = glm::vec3(1.0f);
    EXPECT_FALSE(features(s) & VKP_FEATURE_MEDIA);
    EXPECT_TRUE(features(s) & VKP_FEATURE_ABSORPTION);
    s.materials[0].scatteringAlbedo = glm::vec3(0.5f);
    EXPECT_TRUE(features(s) & VKP_FEATURE_MEDIA);
    s.materials[0].scatteringAlbedo = glm::vec3(0.0f);
    s.fog.scattering = glm::vec3(0.01f);
    EXPECT_TRUE(features(s) & VKP_FEATURE_MEDIA);
}

}  // namespace
