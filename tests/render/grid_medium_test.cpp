// Grid media (render --volume: scene/volume_grid.h, shared/path/media.h):
// OpenVDB files written here with libopenvdb, read back, and rendered where
// the answer is known: Beer-Lambert through a constant grid, single
// scattering in a ramp against its line integral (delta tracking for the
// free flight, ratio tracking for the shadow rays, over cells of different
// majorants), a furnace, and the three executions against each other.
// Bounds: 5 standard errors from the render's own variance AOV.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>

#include "image/statistics.h"
#include "input_error.h"
#include "reference/path_tracer_view.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "scene/scene.h"
#include "scene/volume_grid.h"
#include "shared/features.h"
#include "shared/phase.h"
#include "support/executions.h"
#include "support/gpu_render.h"
#include "support/temp_dir.h"
#include "support/test_scenes.h"
#include "support/vdb_grid.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/kernel_features.h"
#include "wavefront/render_types.h"

namespace {

using namespace vkpath;

constexpr double Z_BOUND = 5.0;

// The grid's density at world point p in double: trilinear between voxel
// centres, 0 outside them (what the kernels compute in float).
double trilinearDensity(const scene::VolumeGrid& grid, const glm::dvec3& p) {
    const glm::dvec3 u = (p - grid.origin) / grid.voxelSize;
    const glm::dvec3 f = glm::floor(u);
    if (f.x < 0 || f.y < 0 || f.z < 0 || f.x + 1 >= grid.resolution.x ||
        f.y + 1 >= grid.resolution.y || f.z + 1 >= grid.resolution.z)
        return 0.0;
    const glm::dvec3 w = u - f;
    double d = 0;
    for (int c = 0; c < 8; ++c) {
        const glm::ivec3 o(c & 1, (c >> 1) & 1, c >> 2);
        d += grid.at(uint32_t(f.x) + o.x, uint32_t(f.y) + o.y, uint32_t(f.z) + o.z) *
             (o.x ? w.x : 1 - w.x) * (o.y ? w.y : 1 - w.y) * (o.z ? w.z : 1 - w.z);
    }
    return d;
}

// The film's mean per channel and its standard error.
std::pair<glm::dvec3, glm::dvec3> filmMean(const wavefront::RenderResult& r) {
    glm::dvec3 mean(0.0), variance(0.0);
    for (size_t p = 0; p < r.image.pixels.size(); ++p) {
        mean += glm::dvec3(r.image.pixels[p]);
        variance += glm::dvec3(r.varianceOfMean.pixels[p]);
    }
    const double n = double(r.image.pixels.size());
    return {mean / n, glm::sqrt(variance) / n};
}

// The file's grid as the loader gives it: the dense array with a voxel of 0
// around the active ones, placed by the file's transform; a grid that is
// not there is one line listing the file's grids, a file that is not a
// grid file one line naming it.
TEST(GridMedium, LoadsTheDenseGridPlacedByItsTransform) {
    const test::TempDir dir;
    const auto path =
        test::writeGrid(dir / "ramp.vdb", 4, 0.5, {1.0, 2.0, 3.0},
                        [](int i, int j, int k) { return float(1 + i + 10 * j + 100 * k); });
    const scene::VolumeGrid g = scene::loadVolumeGrid(path, "density");
    EXPECT_EQ(g.resolution, glm::uvec3(6));
    EXPECT_EQ(g.voxelSize, glm::dvec3(0.5));
    EXPECT_EQ(g.origin, glm::dvec3(0.5, 1.5, 2.5));
    EXPECT_EQ(g.at(0, 0, 0), 0.0f);
    EXPECT_EQ(g.at(1, 1, 1), 1.0f);
    EXPECT_EQ(g.at(4, 2, 3), 1.0f + 3 + 10 + 200);
    EXPECT_EQ(g.at(5, 5, 5), 0.0f);
    try {
        scene::loadVolumeGrid(path, "smoke");
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("no grid named 'smoke' (the file has: density)"),
                  std::string::npos)
            << e.what();
    }
    std::ofstream(dir / "not.vdb") << "not a grid";
    EXPECT_THROW(scene::loadVolumeGrid(dir / "not.vdb", "density"), InputError);
}

// The majorants bound sigma_t: at 10^5 random points of a noisy grid, the
// trilinear density is at most its cell's majorant, and a cell of zeros has
// majorant 0 (thin parts cost nothing).
TEST(GridMedium, MajorantsBoundTheDensityInTheirCells) {
    const test::TempDir dir;
    std::mt19937 random(5);
    std::uniform_real_distribution<float> noise(0.0f, 1.0f);
    const auto path = test::writeGrid(dir / "noise.vdb", 20, 1.0, {0, 0, 0}, [&](int i, int, int) {
        return i < 10 ? 0.0f : noise(random);
    });
    scene::Scene s;
    s.materials.push_back({});
    s.spheres.push_back({"speck", glm::vec3(100.0f), 0.1f, 0});
    s.volume = scene::loadVolumeGrid(path, "density");
    const wavefront::SceneTables t = wavefront::buildSceneTables(s);
    ASSERT_EQ(t.gridMedium.size(), 1u);
    const shared::GridMedium& g = t.gridMedium[0];
    EXPECT_TRUE(wavefront::sceneFeatures(t) & VKP_FEATURE_GRID_MEDIUM);
    EXPECT_EQ(t.gridMajorant[0], 0.0f);  // voxels 0 to 8 along x: all zero
    std::uniform_real_distribution<float> position(0.0f, float(g.resolution.x - 1));
    for (int n = 0; n < 100000; ++n) {
        const glm::vec3 u(position(random), position(random), position(random));
        const glm::uvec3 f(glm::floor(u));
        const glm::vec3 w = u - glm::vec3(f);
        auto at = [&](glm::uvec3 v) {
            return t.gridDensity[(size_t(v.z) * g.resolution.y + v.y) * g.resolution.x + v.x];
        };
        float d = 0;
        for (int c = 0; c < 8; ++c) {
            const glm::uvec3 o(c & 1, (c >> 1) & 1, c >> 2);
            const glm::uvec3 v = glm::min(f + o, g.resolution - 1u);
            d += at(v) * (o.x ? w.x : 1 - w.x) * (o.y ? w.y : 1 - w.y) * (o.z ? w.z : 1 - w.z);
        }
        const glm::uvec3 cell =
            glm::min(glm::uvec3(u / float(g.majorantCell)), g.majorantResolution - 1u);
        const float majorant = t.gridMajorant[(size_t(cell.z) * g.majorantResolution.y + cell.y) *
                                                  g.majorantResolution.x +
                                              cell.x];
        ASSERT_LE(d, majorant * (1 + 1e-6f)) << u.x << " " << u.y << " " << u.z;
    }
}

// Ratio tracking (the shadow rays' transmittance) and delta tracking (the
// free flight's collision) through a noisy ball of smoke, from points inside
// and outside it, along each axis both ways and along diagonals: the mean of
// 4000 ratio-tracked estimates within 5 standard errors of exp(-tau), and
// the fraction of free flights that get through within 5 binomial standard
// errors of it, tau integrated in double from the grid's own trilinear
// density (Simpson's rule, 4000 steps).
TEST(GridMedium, TrackingThroughSmokeIsExpOfTheOpticalDepthInEveryDirection) {
    const test::TempDir dir;
    std::mt19937 random(23);
    std::uniform_real_distribution<float> noise(0.2f, 1.0f);
    const auto path =
        test::writeGrid(dir / "ball.vdb", 32, 1.0 / 16, {-1, -1, -1}, [&](int i, int j, int k) {
            const glm::vec3 p = (glm::vec3(i, j, k) - 15.5f) / 16.0f;
            return glm::length(p) < 1.0f ? noise(random) : 0.0f;
        });
    scene::Scene s;
    s.materials.push_back({});
    s.spheres.push_back({"speck", glm::vec3(0.0f, 0.0f, 50.0f), 0.01f, 0});
    s.volume = scene::loadVolumeGrid(path, "density");
    s.volume->densityScale = 2.0f;
    const wavefront::SceneTables tables = wavefront::buildSceneTables(s);
    const shared::SceneInfo info = wavefront::renderSceneInfo(tables, wavefront::RenderSettings{});
    const shared::PathTracerView view(tables, info);
    const shared::GridMedium g = tables.gridMedium.at(0);
    const scene::VolumeGrid& grid = *s.volume;
    const glm::dvec3 shift = grid.origin - glm::dvec3(g.origin);  // render space
    auto sigmaT = [&](const glm::dvec3& p) {                      // p in world space
        return grid.densityScale * trilinearDensity(grid, p);
    };
    const glm::vec3 starts[] = {{0.1f, 0.2f, -0.15f}, {0.3f, 0.75f, 0.1f}, {-1.6f, 0.1f, 0.05f}};
    const glm::vec3 directions[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0},
                                    {0, 0, 1}, {0, 0, -1}, {1, 1, 1}, {-1, 0.5f, -2}};
    int tracks = 0;
    for (const glm::vec3& start : starts)
        for (const glm::vec3& direction : directions) {
            const glm::vec3 d = glm::normalize(direction);
            const float length = 3.0f;
            double tau = 0;
            const int steps = 4000;
            for (int i = 0; i <= steps; ++i)
                tau += sigmaT(glm::dvec3(start + d * (length * float(i) / steps))) *
                       (i == 0 || i == steps ? 1
                        : i % 2              ? 4
                                             : 2);
            tau *= length / (3.0 * steps);
            if (tau == 0) continue;  // (from outside, away from the ball)
            ++tracks;
            shared::Ray ray;
            ray.origin = start - glm::vec3(shift);
            ray.direction = d;
            ray.tMax = length;
            ray.pixel = 0;
            const int n = 4000;
            double sum = 0, sumSquares = 0, through = 0;
            for (int i = 0; i < n; ++i) {
                const shared::RngKey key = shared::makeRngKey(uint32_t(i), 0u, 77u);
                const double t = view.gridTransmittance(g, ray, length, key);
                sum += t;
                sumSquares += t * t;
                float collision = 0;
                through += view.gridCollision(g, ray, length,
                                              shared::makeRngKey(uint32_t(i), 1u, 78u), collision)
                               ? 0
                               : 1;
            }
            const double mean = sum / n, expected = std::exp(-tau);
            const double error = std::sqrt(std::max(sumSquares / n - mean * mean, 1e-12) / n);
            SCOPED_TRACE(testing::Message()
                         << "from (" << start.x << ", " << start.y << ", " << start.z << ") along ("
                         << d.x << ", " << d.y << ", " << d.z << "): tau " << tau);
            EXPECT_NEAR(mean, expected, Z_BOUND * error + 1e-4);
            EXPECT_NEAR(through / n, expected,
                        Z_BOUND * std::sqrt(expected * (1 - expected) / n) + 1e-4);
        }
    EXPECT_GE(tracks, 16);
}

// The camera at the centre of an emissive sphere of radius 2 inside a grid
// of constant density (sigma_t 0.4 per metre, albedo 0: delta tracking's
// first real collision ends the path), whose voxels reach 3 m from the
// centre: a pixel's mean is exp(-0.8), the film's within 5 standard errors,
// on the GPU and the CPU.
TEST(GridMedium, ConstantGridAbsorbsAsBeerLambert) {
    const test::TempDir dir;
    const auto path = test::writeGrid(dir / "constant.vdb", 25, 0.25, {-3, -3, -3},
                                      [](int, int, int) { return 1.0f; });
    scene::Scene s = test::cameraInsideALampSphere(2.0f);
    s.volume = scene::loadVolumeGrid(path, "density");
    s.volume->densityScale = 0.4f;
    s.volume->albedo = glm::vec3(0.0f);
    const wavefront::RenderSettings settings = test::squareSettings(16, 256, 2, 3);
    for (const bool cpu : {false, true}) {
        SCOPED_TRACE(cpu ? "CPU reference" : "GPU");
        const auto r = cpu ? test::renderCpu(s, settings) : test::renderGpu(s, settings);
        const auto [mean, standardError] = filmMean(r);
        std::printf("  film %.5f +- %.5f, exp(-0.8) %.5f\n", mean.x, standardError.x,
                    std::exp(-0.8));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], std::exp(-0.8), Z_BOUND * standardError[c]);
    }
}

// Single scattering of a point light in a grid whose density is a ramp along
// z (0.2 to 1.8 over 40 m, sigma_t 0.3 per unit), against its line integral:
// with one bounce a path scatters once (delta tracking through cells of
// different majorants) and takes the point light's sample, whose shadow ray
// carries a ratio-tracked transmittance. The integral (in double, the
// grid's own trilinear density, Simpson's rule along the camera ray and
// along each shadow segment, over 6 x 6 directions of the 4-degree film) and
// the film's mean per channel agree within 5 standard errors + 3e-3
// relative (the quadrature's error, measured by doubling its grids: under
// 1e-3).
TEST(GridMedium, SingleScatteringInARampIsItsLineIntegral) {
    const test::TempDir dir;
    const int n = 41;
    const auto ramp = [](int, int, int k) { return 0.2f + 1.6f * float(k) / 40.0f; };
    const auto path = test::writeGrid(dir / "ramp.vdb", n, 1.0, {-20, -20, -20}, ramp);
    const glm::dvec3 albedo(0.9, 0.7, 0.5);
    const double scale = 0.3, g = 0.3, intensity = 10.0, xfov = 4.0;
    scene::Scene s;
    scene::Material black;
    black.reflectance = glm::vec3(0.0f);
    s.materials.push_back(black);
    s.spheres.push_back({"speck", glm::vec3(0.0f, 1.0f, 60.0f), 0.01f, 0});
    s.pointLights.push_back({glm::vec3(0.0f), glm::vec3(float(intensity)), 0.0f});
    s.camera.position = {0.0f, 1.0f, 4.0f};
    s.camera.target = {0.0f, 1.0f, 0.0f};
    s.camera.xfovDegrees = float(xfov);
    s.volume = scene::loadVolumeGrid(path, "density");
    s.volume->densityScale = float(scale);
    s.volume->albedo = glm::vec3(albedo);
    s.volume->anisotropy = float(g);

    const scene::VolumeGrid& grid = *s.volume;
    auto sigmaT = [&](const glm::dvec3& p) { return scale * trilinearDensity(grid, p); };
    auto opticalDepth = [&](const glm::dvec3& a, const glm::dvec3& b, int steps) {
        double sum = 0;
        for (int i = 0; i <= steps; ++i)
            sum += sigmaT(a + (b - a) * (double(i) / steps)) * (i == 0 || i == steps ? 1
                                                                : i % 2              ? 4
                                                                                     : 2);
        return sum * glm::length(b - a) / (3.0 * steps);
    };
    const glm::dvec3 origin(0, 1, 4), light(0, 0, 0);
    auto radiance = [&](const glm::dvec3& w) {
        const int steps = 2000;
        const double tEnd = 50.0, h = tEnd / steps;
        double sum = 0, depth = 0;
        double previous = sigmaT(origin);
        for (int i = 0; i <= steps; ++i) {
            const glm::dvec3 x = origin + (i * h) * w;
            const double sigma = sigmaT(x);
            if (i > 0) depth += 0.5 * h * (previous + sigma);  // trapezoid: depth to x
            previous = sigma;
            const glm::dvec3 toLight = light - x;
            const double d = glm::length(toLight);
            const double phase =
                shared::henyeyGreenstein(float(glm::dot(-w, toLight / d)), float(g));
            const double f = sigma * std::exp(-depth - opticalDepth(x, light, 200)) * phase *
                             intensity / (d * d);
            sum += f * (i == 0 || i == steps ? 1 : i % 2 ? 4 : 2);
        }
        return sum * h / 3;
    };
    const double tanHalf = std::tan(xfov * 0.5 * M_PI / 180.0);
    double integral = 0;
    const int directions = 6;
    for (int j = 0; j < directions; ++j)
        for (int i = 0; i < directions; ++i) {
            const double x = ((i + 0.5) / directions * 2 - 1) * tanHalf;
            const double y = ((j + 0.5) / directions * 2 - 1) * tanHalf;
            integral +=
                radiance(glm::normalize(glm::dvec3(x, y, -1.0))) / (directions * directions);
        }

    const wavefront::RenderSettings settings = test::squareSettings(8, 1024, 1, 9);
    for (const bool cpu : {false, true}) {
        SCOPED_TRACE(cpu ? "CPU reference" : "GPU");
        const auto r = cpu ? test::renderCpu(s, settings) : test::renderGpu(s, settings);
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        const auto [mean, standardError] = filmMean(r);
        for (int c = 0; c < 3; ++c) {
            const double expected = albedo[c] * integral;
            std::printf("  channel %d: film %.6f +- %.6f, integral %.6f\n", c, mean[c],
                        standardError[c], expected);
            EXPECT_NEAR(mean[c], expected, Z_BOUND * standardError[c] + 3e-3 * expected);
        }
    }
}

// Smoke that scatters and does not absorb, under a white sky: light is
// neither made nor lost, so every pixel's expectation is 1. The film's mean
// within 5 standard errors of 1, in each execution (the wavefront and the
// megakernel the same bits). The smoke: a noisy ball of density up to 3 per
// metre, 2 m across; its thin rim and the empty corners make majorant cells
// of very different bounds.
TEST(GridMedium, NonAbsorbingSmokeInAWhiteSkyIsAFurnace) {
    const test::TempDir dir;
    std::mt19937 random(11);
    std::uniform_real_distribution<float> noise(0.5f, 1.0f);
    const auto path =
        test::writeGrid(dir / "smoke.vdb", 32, 1.0 / 16, {-1, -1, -1}, [&](int i, int j, int k) {
            const glm::vec3 p = (glm::vec3(i, j, k) - 15.5f) / 16.0f;
            return glm::length(p) < 1.0f ? 3.0f * noise(random) : 0.0f;
        });
    scene::Scene s;
    s.materials.push_back({});
    s.spheres.push_back({"speck", glm::vec3(0.0f, 0.0f, 50.0f), 0.01f, 0});
    s.camera.position = {0.0f, 0.0f, 4.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 40.0f;
    scene::Environment sky;
    sky.color = glm::vec3(1.0f);
    s.environment = sky;
    s.volume = scene::loadVolumeGrid(path, "density");
    s.volume->anisotropy = 0.5f;
    wavefront::RenderSettings settings = test::squareSettings(24, 16, 256, 13);
    settings.kernel = wavefront::KernelForm::Wavefront;
    const auto wavefrontResult = test::renderGpu(s, settings);
    settings.kernel = wavefront::KernelForm::Megakernel;
    const auto megakernel = test::renderGpu(s, settings);
    EXPECT_TRUE(test::sameBits(wavefrontResult.image, megakernel.image));
    const auto cpu = test::renderCpu(s, settings);
    for (const auto* r : {&megakernel, &cpu}) {
        EXPECT_EQ(r->nonFiniteSamples, 0u);
        const auto [mean, standardError] = filmMean(*r);
        std::printf("  film %.5f +- %.5f\n", mean.y, standardError.y);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], 1.0, Z_BOUND * standardError[c] + 1e-6);
    }
}

// The bundled Cornell box with the smoke ball and a thin fog around it: the
// two GPU kernel forms and the general kernel give the same bits, the CPU
// reference the same image (8 x 8 block z-tests at 1%).
TEST(GridMedium, EveryExecutionRendersTheSameSmokyBox) {
    const test::TempDir dir;
    std::mt19937 random(17);
    std::uniform_real_distribution<float> noise(0.0f, 1.0f);
    const auto path = test::writeGrid(dir / "smoke.vdb", 16, 0.02, {-0.15, 0.05, -0.35},
                                      [&](int, int, int) { return 30.0f * noise(random); });
    scene::Scene s = scene::loadScene(VKPATH_SOURCE_DIR "/assets/cornell_box.gltf");
    s.fog.scattering = glm::vec3(0.3f);
    s.volume = scene::loadVolumeGrid(path, "density");
    s.volume->albedo = {0.9f, 0.8f, 0.7f};
    s.volume->anisotropy = 0.4f;
    wavefront::RenderSettings settings = test::squareSettings(32, 32, 5, 21);
    test::expectEveryExecutionAgrees(s, settings);
}

}  // namespace
