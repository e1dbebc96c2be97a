// Environment maps: the equirectangular mapping shared by CPU and GPU
// (orientation, round trip, agreement between the two compilers), the
// bilinear radiance lookup against hand-computed values, the bundled sky, and
// loadEnvironmentMap's checks of bad files.
#include "scene/environment.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include "image/image.h"
#include "input_error.h"
#include "reference/path_tracer_view.h"
#include "shared/environment_map.h"
#include "support/temp_dir.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"
#include "wavefront/render_types.h"

namespace {

namespace fs = std::filesystem;
using namespace vkpath;

using test::TempDir;

void expectVec3Near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

// The orientation docs/SCENES.md promises.
TEST(EquirectMapping, Orientation) {
    expectVec3Near(shared::equirectDirection(0.5f, 0.0f), {0, 1, 0}, 1e-6f);   // top row: up
    expectVec3Near(shared::equirectDirection(0.5f, 1.0f), {0, -1, 0}, 1e-6f);  // bottom row: down
    expectVec3Near(shared::equirectDirection(0.0f, 0.5f), {0, 0, -1}, 1e-6f);  // left edge: -Z
    expectVec3Near(shared::equirectDirection(0.25f, 0.5f), {1, 0, 0},
                   1e-6f);  // u increases towards +X
    expectVec3Near(shared::equirectDirection(0.5f, 0.5f), {0, 0, 1}, 1e-6f);  // centre: +Z
    expectVec3Near(shared::equirectDirection(0.75f, 0.5f), {-1, 0, 0}, 1e-6f);
    expectVec3Near(shared::equirectDirection(1.0f, 0.5f), {0, 0, -1}, 1e-6f);  // wraps around
    // 45 degrees above the horizon, towards +X.
    const float s = std::sqrt(0.5f);
    expectVec3Near(shared::equirectDirection(0.25f, 0.25f), {s, s, 0}, 1e-6f);
}

TEST(EquirectMapping, RoundTripFromUv) {
    for (int j = 1; j < 64; ++j)  // the poles are a single point each: tested below
        for (int i = 0; i < 128; ++i) {
            const float u = (i + 0.37f) / 128.0f, v = (j + 0.11f) / 64.0f;
            const glm::vec3 d = shared::equirectDirection(u, v);
            EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
            const glm::vec2 uv = shared::equirectUv(d);
            EXPECT_NEAR(uv.x, u, 2e-6f) << u << ", " << v;
            EXPECT_NEAR(uv.y, v, 2e-6f) << u << ", " << v;
        }
}

TEST(EquirectMapping, RoundTripFromDirection) {
    // Directions spread over the sphere (a Fibonacci lattice), back and forth.
    const int n = 2000;
    for (int k = 0; k < n; ++k) {
        const float y = 1.0f - 2.0f * (k + 0.5f) / n;
        const float phi = 2.399963f * k;  // golden angle
        const float r = std::sqrt(1.0f - y * y);
        const glm::vec3 d(r * std::cos(phi), y, r * std::sin(phi));
        const glm::vec2 uv = shared::equirectUv(d);
        EXPECT_GE(uv.x, 0.0f);
        EXPECT_LT(uv.x, 1.0f);
        expectVec3Near(shared::equirectDirection(uv.x, uv.y), d, 2e-6f);
    }
}

TEST(EquirectMapping, PolesAndSeam) {
    EXPECT_EQ(shared::equirectUv({0, 1, 0}), glm::vec2(0.0f, 0.0f));
    EXPECT_EQ(shared::equirectUv({0, -1, 0}), glm::vec2(0.0f, 1.0f));
    // Either side of the seam at -Z: u just below 1, or 0; never 1.
    EXPECT_GT(shared::equirectUv({-1e-6f, 0, -1}).x, 0.999f);
    EXPECT_EQ(shared::equirectUv({0.0f, 0, -1}).x, 0.0f);
    EXPECT_EQ(shared::equirectUv({-0.0f, 0, -1}).x, 0.0f);
    EXPECT_LT(shared::equirectUv({-1e-9f, 0, -1}).x, 1.0f);
}

// The same header compiled as GLSL gives the same directions and the same
// round trip (to a few ulp: GPU transcendentals round differently).
TEST(EquirectMapping, GpuAgreesWithCpu) {
    vk::Context& context = test::context();
    std::vector<glm::vec2> uvs;
    for (int j = 0; j <= 32; ++j)
        for (int i = 0; i < 64; ++i) uvs.push_back({(i + 0.5f) / 64.0f, j / 32.0f});
    const uint32_t count = uint32_t(uvs.size());
    vk::Buffer uvBuffer = vk::Buffer::fromSpan(context, std::span(uvs));
    vk::Buffer directions(context, count * sizeof(glm::vec3));
    vk::Buffer roundTrips(context, count * sizeof(glm::vec2));
    vk::Kernel probe(context, "equirect_probe");
    probe.dispatch(count, {{0, &uvBuffer}, {1, &directions}, {2, &roundTrips}}, count);
    const auto gpuDirections = directions.download<glm::vec3>();
    const auto gpuUvs = roundTrips.download<glm::vec2>();
    for (uint32_t k = 0; k < count; ++k) {
        SCOPED_TRACE(k);
        const glm::vec3 d = shared::equirectDirection(uvs[k].x, uvs[k].y);
        expectVec3Near(gpuDirections[k], d, 1e-5f);
        const bool pole = uvs[k].y == 0.0f || uvs[k].y == 1.0f;
        if (!pole) {
            EXPECT_NEAR(gpuUvs[k].x, uvs[k].x, 1e-5f);
        }
        EXPECT_NEAR(gpuUvs[k].y, uvs[k].y, 1e-5f);
    }
}

// ---------------------------------------------------------------------------
// The bilinear lookup (shared/path_tracer.h environmentRadiance, as the CPU
// reference runs it; tests/kernels/environment_sampling_test.cpp checks that the
// GPU's lookup agrees)
// ---------------------------------------------------------------------------

// A 4 x 2 map whose texels all differ, in a scene of a small sphere (the
// tables need a BVH) under it.
glm::vec3 texel(int x, int y) {
    return {1.0f + x + 4.0f * y, float(1 << (x + 4 * y)), 0.5f};
}

struct EnvironmentView {
    explicit EnvironmentView(float strength = 1.0f, float rotationDegrees = 0.0f) {
        scene::Scene s;
        s.materials.push_back({});
        s.spheres.push_back({"ball", glm::vec3(0.0f), 0.1f, 0});
        scene::Environment env;
        env.map = image::Image(4, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 4; ++x) env.map->at(x, y) = texel(x, y);
        env.strength = strength;
        env.rotationDegrees = rotationDegrees;
        s.environment = env;
        tables = wavefront::buildSceneTables(s);
        info = wavefront::renderSceneInfo(tables, wavefront::RenderSettings{});
    }
    // The radiance seen along the world direction of map coordinates (u, v).
    glm::vec3 at(float u, float v) const {
        const shared::PathTracerView view(tables, info);
        return view.environmentRadiance(
            shared::envMapToWorld(info.environment, shared::equirectDirection(u, v)));
    }
    wavefront::SceneTables tables;
    shared::SceneInfo info;
};

// Texel (x, y)'s centre is (u, v) = ((x + 1/2) / 4, (y + 1/2) / 2); u wraps
// around, v clamps to the edge rows. The expected values are the texels'
// weights worked out by hand.
TEST(EnvironmentLookup, BilinearBetweenTexelCentres) {
    const EnvironmentView env;
    // The direction's round trip to (u, v) is good to ~2e-6 (RoundTripFromUv),
    // 1e-5 of a texel here; a texel-centre convention off by half a texel
    // would be off by tens of percent.
    const float tolerance = 1e-4f;
    auto expectNear = [&](glm::vec3 actual, glm::vec3 expected) {
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(actual[c], expected[c], tolerance * std::max(1.0f, expected[c])) << c;
    };
    {
        SCOPED_TRACE("texel centres");
        expectNear(env.at(0.375f, 0.25f), texel(1, 0));
        expectNear(env.at(0.875f, 0.75f), texel(3, 1));
    }
    {
        SCOPED_TRACE("midway between two centres, and four");
        expectNear(env.at(0.5f, 0.25f), 0.5f * (texel(1, 0) + texel(2, 0)));
        expectNear(env.at(0.375f, 0.5f), 0.5f * (texel(1, 0) + texel(1, 1)));
        expectNear(env.at(0.5f, 0.5f),
                   0.25f * (texel(1, 0) + texel(2, 0) + texel(1, 1) + texel(2, 1)));
    }
    {
        SCOPED_TRACE("a quarter of the way in each direction: x = 1.25, y = 0.25");
        expectNear(env.at(0.4375f, 0.375f), 0.5625f * texel(1, 0) + 0.1875f * texel(2, 0) +
                                                0.1875f * texel(1, 1) + 0.0625f * texel(2, 1));
    }
    {
        SCOPED_TRACE("across the seam at u = 0 (-Z): the last column and the first");
        expectNear(env.at(0.0f, 0.25f), 0.5f * (texel(3, 0) + texel(0, 0)));
        expectNear(env.at(0.0625f, 0.25f), 0.25f * texel(3, 0) + 0.75f * texel(0, 0));
        expectNear(env.at(0.9375f, 0.25f), 0.75f * texel(3, 0) + 0.25f * texel(0, 0));
        expectNear(env.at(0.0f, 0.5f),
                   0.25f * (texel(3, 0) + texel(0, 0) + texel(3, 1) + texel(0, 1)));
    }
    {
        SCOPED_TRACE("within half a texel of a pole: the edge row alone");
        expectNear(env.at(0.375f, 0.1f), texel(1, 0));
        expectNear(env.at(0.5f, 0.05f), 0.5f * (texel(1, 0) + texel(2, 0)));
        expectNear(env.at(0.625f, 0.9f), texel(2, 1));
    }
    {
        SCOPED_TRACE(
            "the poles themselves: u = 0 there (equirectUv), midway between columns 3 and 0");
        const shared::PathTracerView view(env.tables, env.info);
        expectNear(view.environmentRadiance({0, 1, 0}), 0.5f * (texel(3, 0) + texel(0, 0)));
        expectNear(view.environmentRadiance({0, -1, 0}), 0.5f * (texel(3, 1) + texel(0, 1)));
    }
}

TEST(EnvironmentLookup, StrengthAndRotationApply) {
    const EnvironmentView env(2.0f, 73.0f);
    const glm::vec3 expected = 0.5625f * texel(1, 0) + 0.1875f * texel(2, 0) +
                               0.1875f * texel(1, 1) + 0.0625f * texel(2, 1);
    const glm::vec3 actual =
        env.at(0.4375f, 0.375f);  // the map direction, turned to the world by 73 degrees
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(actual[c], 2.0f * expected[c], 1e-4f * 2.0f * expected[c]) << c;
}

// ---------------------------------------------------------------------------
// The bundled sky (tools/make-assets)
// ---------------------------------------------------------------------------

TEST(EnvironmentMap, BundledSkyLoadsWithTheSunWhereTheGeneratorPutIt) {
    testing::internal::CaptureStderr();
    const image::Image sky = scene::loadEnvironmentMap(test::sourcePath("assets/sky.hdr"));
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    ASSERT_EQ(sky.width, 2048u);
    ASSERT_EQ(sky.height, 1024u);

    // The brightest texel: the sun, 35 degrees up at u = 0.625.
    size_t brightest = 0;
    for (size_t i = 0; i < sky.pixels.size(); ++i)
        if (sky.pixels[i].y > sky.pixels[brightest].y) brightest = i;
    const float u = (brightest % sky.width + 0.5f) / sky.width,
                v = (brightest / sky.width + 0.5f) / sky.height;
    const glm::vec3 sun = shared::equirectDirection(u, v);
    EXPECT_NEAR(glm::degrees(std::asin(sun.y)), 35.0f, 0.3f);
    const glm::vec3 expected = shared::equirectDirection(0.625f, (90.0f - 35.0f) / 180.0f);
    EXPECT_LT(glm::degrees(std::acos(std::min(1.0f, glm::dot(sun, expected)))), 0.3f);

    // About 1e5 times the sky; the sky is a smooth gradient, brighter at the horizon than the
    // zenith.
    std::vector<float> greens;
    for (const glm::vec3& p : sky.pixels) greens.push_back(p.y);
    std::nth_element(greens.begin(), greens.begin() + greens.size() / 2, greens.end());
    const float median = greens[greens.size() / 2];
    EXPECT_GT(sky.pixels[brightest].y / median, 3e4f);
    EXPECT_LT(sky.pixels[brightest].y / median, 3e5f);
    const glm::vec3 zenith = sky.at(0, 0), horizon = sky.at(0, sky.height / 2 - 1),
                    ground = sky.at(0, sky.height - 1);
    EXPECT_GT(horizon.y, zenith.y);
    EXPECT_GT(zenith.z, zenith.x);  // blue overhead
    EXPECT_LT(ground.y, horizon.y);
    for (uint32_t y = 1; y + 1 < sky.height / 2; ++y)  // smooth: no jumps between rows of the sky
        EXPECT_LT(std::abs(sky.at(0, y).y - sky.at(0, y - 1).y), 0.02f) << y;
}

// ---------------------------------------------------------------------------
// Bad maps
// ---------------------------------------------------------------------------

std::string loadError(const fs::path& path, uint64_t maxPixels = scene::MAX_ENVIRONMENT_PIXELS) {
    try {
        scene::loadEnvironmentMap(path, maxPixels);
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
        return message;
    }
    ADD_FAILURE() << path << " loaded without an error";
    return {};
}

TEST(EnvironmentMap, MissingFile) {
    TempDir dir;
    EXPECT_NE(loadError(dir / "absent.exr").find("no such file"), std::string::npos);
}

TEST(EnvironmentMap, UnreadableFile) {
    TempDir dir;
    std::ofstream(dir / "garbage.exr") << "this is not an OpenEXR file";
    EXPECT_NE(loadError(dir / "garbage.exr").find("cannot read"), std::string::npos);
}

TEST(EnvironmentMap, OversizedMapIsRejectedBeforeReading) {
    TempDir dir;
    image::writeExr(dir / "big.exr", image::Image(64, 32));
    EXPECT_NE(loadError(dir / "big.exr", 1000).find("exceed the limit of 1000"), std::string::npos);
    EXPECT_EQ(scene::loadEnvironmentMap(dir / "big.exr", 2048).width, 64u);
}

TEST(EnvironmentMap, NonFiniteTexelIsAnError) {
    TempDir dir;
    for (float bad :
         {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        image::Image map(8, 4);
        map.at(5, 2) = {1.0f, bad, 1.0f};
        image::writeExr(dir / "bad.exr", map);
        EXPECT_NE(loadError(dir / "bad.exr").find("texel (5, 2) is not finite"), std::string::npos);
    }
}

TEST(EnvironmentMap, NegativeTexelsAreClampedWithOneWarning) {
    TempDir dir;
    image::Image map(8, 4);
    map.at(1, 1) = {-0.5f, 1.0f, 2.0f};
    map.at(2, 3) = {-1.0f, -1.0f, 0.5f};
    image::writeExr(dir / "negative.exr", map);
    testing::internal::CaptureStderr();
    const image::Image loaded = scene::loadEnvironmentMap(dir / "negative.exr");
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_EQ(warnings, "vkpath: warning: " + (dir / "negative.exr").string() +
                            ": 3 negative texel values clamped to 0\n");
    EXPECT_EQ(loaded.at(1, 1), glm::vec3(0.0f, 1.0f, 2.0f));
    EXPECT_EQ(loaded.at(2, 3), glm::vec3(0.0f, 0.0f, 0.5f));
}

TEST(EnvironmentMap, NonEquirectangularAspectWarns) {
    TempDir dir;
    image::writeExr(dir / "square.exr", image::Image(16, 16));
    testing::internal::CaptureStderr();
    scene::loadEnvironmentMap(dir / "square.exr");
    const std::string warnings = testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("16x16 is not 2:1"), std::string::npos) << warnings;
}

}  // namespace
