// The wavefront path tracer against scenes whose answer is known exactly
// (furnaces, mirrors, invisible glass), plus determinism and no NaN/Inf, also
// when waves are cut smaller (a time cap per wave, a device-memory bound) or
// the film is kept in windows.
// Tolerances are z-tests with the standard error measured by the render's own
// variance AOV: a bound of 5 standard errors has a false-alarm rate of
// 6e-7 per check, so a failure means a bias, not bad luck.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "image/statistics.h"
#include "input_error.h"
#include "scene/scene.h"
#include "support/gpu_render.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

constexpr double Z_BOUND = 5.0;

using test::render;
using test::sphereInEnvironment;

// Pixels whose whole footprint sees the sphere (radius 1 at distance 4, 40
// degree fov: the sphere spans about 0.73 of the half-width), and pixels
// that see only the environment.
bool onSphere(uint32_t x, uint32_t y, uint32_t size) {
    const double cx = (x + 0.5) / size * 2 - 1, cy = (y + 0.5) / size * 2 - 1;
    return cx * cx + cy * cy < 0.6 * 0.6;
}
bool offSphere(uint32_t x, uint32_t y, uint32_t size) {
    const double cx = (x + 0.5) / size * 2 - 1, cy = (y + 0.5) / size * 2 - 1;
    return cx * cx + cy * cy > 0.85 * 0.85;
}

void expectRegion(const wavefront::RenderResult& r, bool sphere, double expected) {
    const auto region = image::regionMean(r.image, r.varianceOfMean, [&](uint32_t x, uint32_t y) {
        return sphere ? onSphere(x, y, r.image.width) : offSphere(x, y, r.image.width);
    });
    ASSERT_GT(region.pixels, 100u);
    EXPECT_NEAR(region.mean, expected, Z_BOUND * region.standardError + 1e-6)
        << "standard error " << region.standardError;
}

// White furnace: a diffuse sphere of albedo 1 in a constant environment of
// radiance 1 is invisible: every pixel is 1 (light sampling and BSDF
// sampling, combined by MIS, must add up).
TEST(Furnace, WhiteSphereIsInvisible) {
    for (uint32_t lightSamples : {1u, 3u}) {
        SCOPED_TRACE(lightSamples);
        const auto r = render(sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(1.0f)),
                              16, 8, 48, 1, lightSamples);
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        expectRegion(r, true, 1.0);
        expectRegion(r, false, 1.0);
    }
}

// Albedo 0.5: the sphere is convex, so light reflects once and escapes:
// 0.5 for any depth >= 1, 0 at depth 0 (only emitters are seen).
TEST(Furnace, GreySphereReflectsItsAlbedo) {
    const auto grey = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.5f));
    expectRegion(render(grey, 16, 3), true, 0.5);
    expectRegion(render(grey, 4, 0), true, 0.0);
}

// Inside a closed emissive sphere of albedo rho and emitted radiance 1, the
// radiance after at most m bounces is the geometric series sum_{k=0..m} rho^k
// (every bounce sees the same emitter and reflects rho of it). Exercises
// sampling a sphere light from inside it, and MIS with area lights.
TEST(Furnace, InsideAnEmitterGivesTheGeometricSeries) {
    for (float rho : {0.5f, 0.9f})
        for (uint32_t depth : {0u, 1u, 5u}) {
            SCOPED_TRACE(testing::Message() << "albedo " << rho << " depth " << depth);
            scene::Scene s;
            scene::Material m;
            m.reflectance = glm::vec3(rho);
            m.emission = glm::vec3(1.0f);
            s.materials.push_back(m);
            s.spheres.push_back({"room", glm::vec3(0.0f, 0.5f, 0.0f), 3.0f, 0});
            s.camera.position = {0.0f, 0.0f, 0.0f};
            s.camera.target = {0.0f, 0.0f, -1.0f};
            s.camera.xfovDegrees = 60.0f;
            const auto r = render(s, 8, depth, 32);
            double expected = 0;
            for (uint32_t k = 0; k <= depth; ++k) expected += std::pow(double(rho), double(k));
            const auto region = image::regionMean(r.image, r.varianceOfMean,
                                                  [](uint32_t, uint32_t) { return true; });
            EXPECT_NEAR(region.mean, expected, Z_BOUND * region.standardError + 1e-5 * expected);
            EXPECT_EQ(r.nonFiniteSamples, 0u);
        }
}

// A mirror sphere of reflectance 0.7 in a constant environment of radiance 1
// shows exactly 0.7 (no noise: the mirror is deterministic).
TEST(Specular, MirrorSphereShowsItsReflectance) {
    const auto r = render(sphereInEnvironment(scene::MaterialKind::Mirror, glm::vec3(0.7f)), 2, 8);
    for (uint32_t y = 0; y < r.image.height; ++y)
        for (uint32_t x = 0; x < r.image.width; ++x)
            if (onSphere(x, y, r.image.width)) {
                ASSERT_NEAR(r.image.at(x, y).x, 0.7f, 1e-5f) << x << "," << y;
            }
}

// Glass of index 1 is no interface: a scene with a glass ball of ior 1 in
// front of a diffuse floor lit by the environment and an area light renders
// the same as the scene without it (8x8 blocks, Welch z-tests, 1% false-alarm
// rate over all blocks). Light reaches the floor under the ball only through
// BSDF sampling (shadow rays stop at glass), which MIS then weights fully: the
// estimate stays unbiased. A point light could not shine through glass at all.
TEST(Specular, GlassOfIndexOneIsInvisible) {
    auto base = [] {
        scene::Scene s;
        scene::Material floor;
        floor.reflectance = glm::vec3(0.6f, 0.4f, 0.3f);
        s.materials.push_back(floor);
        scene::Material glass;
        glass.kind = scene::MaterialKind::Dielectric;
        glass.reflectance = glm::vec3(1.0f);
        glass.ior = 1.0f;
        s.materials.push_back(glass);
        scene::Mesh mesh;
        mesh.positions = {{-5, -1, -5}, {5, -1, -5}, {5, -1, 5}, {-5, -1, 5}};
        mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
        s.meshes.push_back(mesh);
        s.camera.position = {0, 1, 4};
        s.camera.target = {0, -0.5f, 0};
        s.camera.xfovDegrees = 50;
        scene::Environment env;
        env.color = glm::vec3(0.8f, 0.9f, 1.0f);
        s.environment = env;
        scene::Material lamp;
        lamp.emission = glm::vec3(6.0f);
        s.materials.push_back(lamp);
        scene::Mesh quad;
        quad.positions = {
            {-0.5f, 2.5f, -0.5f}, {0.5f, 2.5f, -0.5f}, {0.5f, 2.5f, 0.5f}, {-0.5f, 2.5f, 0.5f}};
        quad.triangles = {{0, 1, 2}, {0, 2, 3}};
        quad.material = 2;
        s.meshes.push_back(quad);
        return s;
    };
    scene::Scene without = base();
    scene::Scene with = base();
    with.spheres.push_back({"glass", glm::vec3(0, 0, 0), 0.8f, 1});
    const auto a = render(without, 32, 6, 48, 1);
    const auto b = render(with, 32, 6, 48, 2);
    const auto c =
        image::compareBlocks(a.image, a.varianceOfMean, b.image, b.varianceOfMean, 8, 0.01);
    EXPECT_EQ(c.rejected, 0) << "worst z " << c.worstZ << " over " << c.blocks << " blocks";
}

// The block comparison has power: glass of index 1.5 is visible.
TEST(Specular, GlassOfIndexOnePointFiveIsVisible) {
    scene::Scene s = sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(1.0f), 1.5f);
    s.environment.reset();
    s.pointLights.push_back({glm::vec3(2, 3, 3), glm::vec3(30.0f)});
    scene::Material floor;
    s.materials.push_back(floor);
    scene::Mesh mesh;
    mesh.positions = {{-5, -1, -5}, {5, -1, -5}, {5, -1, 5}, {-5, -1, 5}};
    mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
    mesh.material = 1;
    s.meshes.push_back(mesh);
    scene::Scene invisible = s;
    invisible.materials[0].ior = 1.0f;
    const auto a = render(s, 32, 6, 48, 1);
    const auto b = render(invisible, 32, 6, 48, 2);
    EXPECT_GT(image::compareBlocks(a.image, a.varianceOfMean, b.image, b.varianceOfMean, 8, 0.01)
                  .rejected,
              0);
}

TEST(Determinism, SameSeedSameBits) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    const auto a = render(s, 4, 8, 32, 7), b = render(s, 4, 8, 32, 7), c = render(s, 4, 8, 32, 8);
    ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
    EXPECT_EQ(std::memcmp(a.image.pixels.data(), b.image.pixels.data(),
                          a.image.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_NE(std::memcmp(a.image.pixels.data(), c.image.pixels.data(),
                          a.image.pixels.size() * sizeof(glm::vec3)),
              0);
}

// Many waves give the same image as one: the wave size changes which paths
// share a command buffer, never the numbers.
TEST(Determinism, WaveSizeDoesNotChangeTheImage) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    wavefront::RenderSettings settings;
    settings.width = settings.height = 24;
    settings.samplesPerPixel = 6;
    settings.seed = 3;
    wavefront::GpuRenderer one(test::context(), s, settings);
    const auto a = one.render();
    settings.maxPathsInFlight = 24 * 24 * 2;  // 3 waves of 2 samples
    wavefront::GpuRenderer three(test::context(), s, settings);
    const auto b = three.render();
    EXPECT_EQ(a.waves, 1u);
    EXPECT_EQ(b.waves, 3u);
    EXPECT_EQ(std::memcmp(a.image.pixels.data(), b.image.pixels.data(),
                          a.image.pixels.size() * sizeof(glm::vec3)),
              0);
}

TEST(TimeBudget, StopsWithinOneWave) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    wavefront::RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 100000;
    settings.maxPathsInFlight = 32 * 32;  // one sample per wave
    settings.timeBudgetSeconds = 0.5;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    EXPECT_LT(r.samplesPerPixel, 100000u);
    EXPECT_GE(r.samplesPerPixel, 1u);
    const double perWave = r.seconds / r.waves;
    EXPECT_GE(r.seconds, 0.5);
    EXPECT_LE(r.seconds, 0.5 + perWave * 1.5 + 0.05) << r.waves << " waves";
}

// Waves capped in time (here so tightly that every wave is one workgroup of
// 64 paths, which does not divide the 600 pixels) still end at every whole
// sample, so a checkpoint comes after each; and the image is the uncapped one.
TEST(MaxWaveMs, WavesStillEndAtEveryWholeSampleAndKeepTheImage) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    wavefront::RenderSettings settings;
    settings.width = 30;
    settings.height = 20;
    settings.samplesPerPixel = 6;
    wavefront::GpuRenderer whole(test::context(), s, settings);
    const auto a = whole.render();
    settings.maxWaveMilliseconds = 1e-6;
    wavefront::GpuRenderer capped(test::context(), s, settings);
    std::vector<uint32_t> checkpoints;
    wavefront::RenderControl control;
    control.checkpoint = [&](const wavefront::RenderState& state) {
        checkpoints.push_back(state.samplesDone);
    };
    const auto b = capped.render(wavefront::SampleRange{0, 6}, control);
    EXPECT_EQ(a.waves, 1u);
    EXPECT_EQ(b.waves, 6u * 10u) << "600 pixels: nine waves of 64 paths and one of 24 per sample";
    EXPECT_EQ(b.cappedWavePaths, 64u);
    EXPECT_EQ(checkpoints, (std::vector<uint32_t>{1, 2, 3, 4, 5, 6}));
    EXPECT_EQ(std::memcmp(a.image.pixels.data(), b.image.pixels.data(),
                          a.image.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_EQ(std::memcmp(a.varianceOfMean.pixels.data(), b.varianceOfMean.pixels.data(),
                          a.varianceOfMean.pixels.size() * sizeof(glm::vec3)),
              0);
}

// Out of device memory the paths in flight shrink (wavefront/renderer.cpp);
// lavapipe never runs out for a buffer, so this takes the bound a user sets
// with --max-device-memory: the scene, film and path state stay under it,
// with fewer paths per wave and the same image.
TEST(DeviceMemory, BoundMakesWavesSmallerNotTheImage) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    wavefront::RenderSettings settings;
    settings.width = settings.height = 32;
    settings.samplesPerPixel = 8;
    settings.kernel = wavefront::KernelForm::Wavefront;
    wavefront::GpuRenderer whole(test::context(), s, settings);
    const auto a = whole.render();
    auto total = [](const wavefront::GpuRenderer& r) {
        uint64_t bytes = 0;
        for (const wavefront::MemoryGroup& g : r.memory()) bytes += g.bytes;
        return bytes;
    };
    // Room for a third of the path state: two samples per wave.
    const uint64_t pathState = whole.memory().at(1).bytes;
    settings.maxDeviceMemoryBytes = total(whole) - pathState + pathState / 3;
    wavefront::GpuRenderer bounded(test::context(), s, settings);
    EXPECT_EQ(bounded.pathsInFlight(), 32u * 32u * 2u);
    EXPECT_LE(total(bounded), *settings.maxDeviceMemoryBytes);
    const auto b = bounded.render();
    EXPECT_EQ(a.waves, 1u);
    EXPECT_EQ(b.waves, 4u);
    EXPECT_EQ(std::memcmp(a.image.pixels.data(), b.image.pixels.data(),
                          a.image.pixels.size() * sizeof(glm::vec3)),
              0);
    // No room for one workgroup of paths: refused, naming the flag.
    settings.maxDeviceMemoryBytes = total(whole) - pathState;
    EXPECT_THROW(wavefront::GpuRenderer(test::context(), s, settings), InputError);
}

// A wave never holds more paths (or shadow rays) than one dispatch reaches:
// lavapipe allows 65535 workgroups, so with one-invocation workgroups a wave
// of 48 x 32 pixels at 64 spp (98304 paths) must be cut, in both kernel forms
// and with three shadow rays per vertex, where it used to stop the render
// with "the device allows 65535" (the megakernel with --paths-in-flight above
// 4194304). The image stays that of 64-wide workgroups.
TEST(PathsInFlight, CutToWhatOneDispatchReaches) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    const uint32_t maxGroups = test::context().info().maxWorkgroupCount[0];
    for (const auto form : {wavefront::KernelForm::Megakernel, wavefront::KernelForm::Wavefront}) {
        SCOPED_TRACE(wavefront::kernelFormName(form));
        wavefront::RenderSettings settings;
        settings.width = 48;
        settings.height = 32;
        settings.samplesPerPixel = 64;
        settings.maxDepth = 2;
        settings.lightSamples = 3;
        settings.kernel = form;
        const auto wide = wavefront::GpuRenderer(test::context(), s, settings).render();
        settings.workgroupSize = 1;
        wavefront::GpuRenderer narrow(test::context(), s, settings);
        const uint64_t shadowRays = form == wavefront::KernelForm::Wavefront ? 3 : 1;
        EXPECT_LE(narrow.pathsInFlight() * shadowRays, maxGroups);
        const auto r = narrow.render();
        // (A GPU that allows 2^31 - 1 workgroups, as NVIDIA's, needs no cut.)
        EXPECT_EQ(r.waves > 1, 48u * 32u * 64u * shadowRays > maxGroups);
        EXPECT_EQ(std::memcmp(r.image.pixels.data(), wide.image.pixels.data(),
                              r.image.pixels.size() * sizeof(glm::vec3)),
                  0);
    }
}

// A film larger than one storage binding or one dispatch is kept in windows
// (wavefront/renderer.cpp filmWindowPixels): 1200 pixels in windows of 7, the
// last one short, give the one-window image and variance bit for bit, and a
// checkpoint's film bytes are the same pixel-order bytes.
TEST(FilmWindows, ManyWindowsGiveTheSameImageAndState) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    wavefront::RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = 3;
    auto renderWith = [&](uint32_t windowPixels, wavefront::RenderState& state) {
        settings.filmWindowPixels = windowPixels;
        wavefront::GpuRenderer renderer(test::context(), s, settings);
        wavefront::RenderControl control;
        control.checkpoint = [&](const wavefront::RenderState& st) { state = st; };
        return renderer.render(wavefront::SampleRange{0, 3}, control);
    };
    wavefront::RenderState oneState, manyState;
    const auto one = renderWith(0, oneState);
    const auto many = renderWith(7, manyState);
    EXPECT_EQ(std::memcmp(one.image.pixels.data(), many.image.pixels.data(),
                          one.image.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_EQ(std::memcmp(one.varianceOfMean.pixels.data(), many.varianceOfMean.pixels.data(),
                          one.varianceOfMean.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_EQ(oneState.film, manyState.film);
    // Resuming a windowed render from the one-window state continues it exactly.
    settings.samplesPerPixel = 5;
    settings.filmWindowPixels = 7;
    wavefront::GpuRenderer resumed(test::context(), s, settings);
    wavefront::RenderControl control;
    control.resume = &oneState;
    const auto r = resumed.render(wavefront::SampleRange{0, 5}, control);
    settings.filmWindowPixels = 0;
    wavefront::GpuRenderer whole(test::context(), s, settings);
    const auto w = whole.render();
    EXPECT_EQ(std::memcmp(r.image.pixels.data(), w.image.pixels.data(),
                          w.image.pixels.size() * sizeof(glm::vec3)),
              0);
}

// On the device's own limits: lavapipe binds at most 128 MiB (2796202 film
// pixels of 48 bytes) and accumulate's one thread per pixel reaches 65535 x 64
// = 4194240 pixels in one dispatch, so 2048 x 2100 pixels (4.3 M) need two
// windows for either reason. Emission only (-m 0, 1 spp) of a black sphere in
// a white environment: the left and right columns see only the environment
// (exactly 1) in every row, the middle the sphere (exactly 0); a window left
// unaccumulated would read 0 everywhere.
TEST(FilmWindows, AFilmLargerThanOneBindingAndOneDispatchRenders) {
    const auto s = sphereInEnvironment(scene::MaterialKind::Diffuse, glm::vec3(0.6f));
    wavefront::RenderSettings settings;
    settings.width = 2048;
    settings.height = 2100;
    settings.samplesPerPixel = 1;
    settings.maxDepth = 0;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    const image::Image& img = r.image;
    uint32_t wrong = 0;
    for (uint32_t y = 0; y < img.height; ++y)
        wrong += img.at(0, y) != glm::vec3(1.0f) || img.at(img.width - 1, y) != glm::vec3(1.0f);
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(img.at(img.width / 2, img.height / 2), glm::vec3(0.0f));
    EXPECT_EQ(img.at(img.width / 2, img.height * 3 / 4), glm::vec3(0.0f)) << "in the second window";
    EXPECT_EQ(r.nonFiniteSamples, 0u);
}

}  // namespace
