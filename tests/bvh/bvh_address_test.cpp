// Scenes larger than a storage-buffer binding (maxStorageBufferRange, 128 MiB
// on lavapipe) are read by buffer device address (shared/bvh_buffers.h). The
// tests take that path with small scenes by lowering the binding limit
// (VKPATH_MAX_BINDING_BYTES) or choosing it directly, and compare it with the
// bound path hit for hit and pixel for pixel; one test renders a scene of
// 3 million triangles (144 MiB of primitives).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "bvh/gpu_bvh.h"
#include "bvh_test_util.h"
#include "input_error.h"
#include "scene/load.h"
#include "support/binding_limit.h"
#include "vk/context.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

using test::BindingLimit;

TEST(BvhAddress, LimitsChooseThePath) {
    const vk::BufferLimits limits{1000, 5000};
    const vk::ArrayExtent small{"small", 1000, 10}, medium{"medium", 1001, 11},
        large{"too large", 5001, 50};
    EXPECT_FALSE(vk::chooseAddressAccess(std::span(&small, 1), limits));
    EXPECT_TRUE(vk::chooseAddressAccess(std::span(&medium, 1), limits));
    const vk::ArrayExtent all[] = {small, large};
    try {
        vk::chooseAddressAccess(all, limits);
        ADD_FAILURE() << "no InputError for an array beyond the address limit";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("too large array"), std::string::npos) << message;
        EXPECT_NE(message.find("50 elements"), std::string::npos) << message;
    }

    const vk::DeviceInfo& device = test::context().info();
    const vk::BufferLimits real = vk::bufferLimits(device);
    EXPECT_EQ(real.binding, 16ull * device.maxTexelBufferElements);
    {
        // A device whose texel buffers reach less far (the spec's minimum,
        // 65536 texels) binds only what they reach: beyond it, the address path.
        vk::DeviceInfo few = device;
        few.maxTexelBufferElements = 65536;
        EXPECT_EQ(vk::bufferLimits(few).binding, 1u << 20);
    }
    // On lavapipe both reach 2 GiB (a buffer's and a texel buffer's limit);
    // on devices whose buffers reach further, the address path takes over.
    EXPECT_GE(real.address, real.binding) << "the address path must reach as far as a binding";
    {
        const BindingLimit lowered(1 << 20);
        EXPECT_EQ(vk::bufferLimits(device).binding, 1u << 20);
        EXPECT_EQ(vk::bufferLimits(device).address, real.address);
    }
    {
        const BindingLimit junk(0);
        EXPECT_THROW(vk::bufferLimits(device), InputError);
    }
}

class BvhAddressScene : public testing::TestWithParam<const char*> {};

// The trace kernels built for the address path return what the bound path
// returns, bit for bit, on 10^5 random rays.
TEST_P(BvhAddressScene, TraversalEqualsTheBoundPath) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = scene::loadScene(test::sharedScene(GetParam()));
    const bvh::BvhBuild build = buildChecked(s);
    const vec3 lo = build.nodes[0].boundsMin, hi = build.nodes[0].boundsMax;
    const vec3 margin = 0.25f * (hi - lo);
    const std::vector<Ray> rays = randomRays(build, 100000, 77, lo - margin, hi + margin);

    GpuTracer bound(test::context(), build, false);
    GpuTracer addressed(test::context(), build, true);
    const std::vector<Hit> a = bound.closest(rays), b = addressed.closest(rays);
    size_t differences = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        differences += std::memcmp(&a[i], &b[i], sizeof(Hit)) != 0;
        hits += a[i].primitive != VKP_NO_HIT;
    }
    EXPECT_EQ(differences, 0u);
    EXPECT_GT(hits, rays.size() / 3);
    EXPECT_EQ(bound.occluded(rays), addressed.occluded(rays));
}

// The whole renderer on the address path (every scene array by address)
// gives the same image as on the bound path: the same paths, the same sums.
TEST_P(BvhAddressScene, RenderEqualsTheBoundPath) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = scene::loadScene(test::sharedScene(GetParam()));
    wavefront::RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    settings.samplesPerPixel = 4;
    settings.seed = 5;
    wavefront::GpuRenderer bound(test::context(), s, settings);
    ASSERT_FALSE(bound.scene().byAddress);
    const wavefront::RenderResult a = bound.render();

    // The lowest limit the materials (always bound) allow; the BVH's nodes or
    // primitives are larger.
    const uint64_t materialBytes = bound.tables().materials.size() * sizeof(shared::Material);
    const uint64_t bvhBytes =
        std::max(bound.scene().bvh.nodes.size(), bound.scene().bvh.primitives.size());
    ASSERT_GT(bvhBytes, materialBytes);
    const BindingLimit lowered(materialBytes);
    wavefront::GpuRenderer addressed(test::context(), s, settings);
    ASSERT_TRUE(addressed.scene().byAddress);
    const wavefront::RenderResult b = addressed.render();
    ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
    size_t differences = 0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i)
        differences += a.image.pixels[i] != b.image.pixels[i];
    EXPECT_EQ(differences, 0u);
    EXPECT_EQ(a.paths, b.paths);
}

INSTANTIATE_TEST_SUITE_P(Scotty3d, BvhAddressScene, testing::Values("bunny.dae", "carim_glass.dae"),
                         [](const testing::TestParamInfo<const char*>& p) {
                             std::string name = p.param;
                             return name.substr(0, name.find('.'));
                         });

// A square grid of cells x cells quads (2 cells^2 triangles) in the plane
// y = 0, diffuse with albedo 0.5, under a constant white sky, seen from
// straight above. Every camera ray hits the plane, which sees only the sky
// above it, so every pixel's expected value is albedo x sky = 0.5 exactly.
scene::Scene litGrid(uint32_t cells) {
    scene::Scene s;
    scene::Material m;
    m.reflectance = vec3(0.5f);
    s.materials.push_back(m);
    scene::Mesh mesh;
    mesh.name = "grid";
    const uint32_t n = cells + 1;
    mesh.positions.reserve(size_t(n) * n);
    for (uint32_t z = 0; z < n; ++z)
        for (uint32_t x = 0; x < n; ++x)
            mesh.positions.emplace_back(float(x) / cells * 2.0f - 1.0f, 0.0f,
                                        float(z) / cells * 2.0f - 1.0f);
    mesh.triangles.reserve(size_t(cells) * cells * 2);
    for (uint32_t z = 0; z < cells; ++z)
        for (uint32_t x = 0; x < cells; ++x) {
            const uint32_t i = z * n + x;
            mesh.triangles.emplace_back(i, i + n, i + 1);
            mesh.triangles.emplace_back(i + 1, i + n, i + n + 1);
        }
    s.meshes.push_back(std::move(mesh));
    scene::Environment sky;
    sky.color = vec3(1.0f);
    s.environment = sky;
    s.camera.position = {0.0f, 1.0f, 0.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.up = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = 60.0f;
    return s;
}

// 2 x 300^2 = 180 000 triangles, 8.2 MiB of primitives, on a device held
// to bindings of 4 MiB: the renderer as a whole on a scene whose arrays
// are read by address (on lavapipe, beyond 2 GiB).
TEST(BvhAddress, LargeSceneRenders) {
    const scene::Scene s = litGrid(300);
    constexpr uint64_t BINDING = uint64_t(4) << 20;
    const BindingLimit held(BINDING);

    wavefront::RenderSettings settings;
    settings.width = 16;
    settings.height = 16;
    settings.samplesPerPixel = 16;
    settings.maxDepth = 2;
    wavefront::GpuRenderer renderer(test::context(), s, settings);
    EXPECT_GT(renderer.scene().bvh.primitives.size(), BINDING);
    EXPECT_TRUE(renderer.scene().byAddress);
    RecordProperty("scene_bytes", std::to_string(renderer.sceneBytes()));
    const wavefront::RenderResult r = renderer.render();

    // The image mean (green: the channels are equal) against 0.5, with the
    // standard error from the pixels' own variance estimates; 5 sigma (a
    // false alarm ~ 6e-7).
    double sum = 0, variance = 0;
    const size_t pixels = r.image.pixels.size();
    for (size_t i = 0; i < pixels; ++i) {
        sum += r.image.pixels[i].y;
        variance += r.varianceOfMean.pixels[i].y;
    }
    const double mean = sum / double(pixels);
    const double sigma = std::sqrt(variance) / double(pixels);
    EXPECT_NEAR(mean, 0.5, 5 * sigma + 1e-6) << "sigma " << sigma;
    EXPECT_EQ(r.nonFiniteSamples, 0u);
}

}  // namespace
