// Traversal on the Scotty3D scenes, loaded through scene::loadScene: the bunny
// (33696 triangles) and the Cornell box with two spheres. 10^5 random rays per
// scene: the GPU kernels must agree with the CPU traversal (the same shared
// code) on every ray, and with brute force (every primitive, on every
// hardware thread) on as many rays as the CI time budget allows: all of them
// for CBspheres, 2967 for the bunny (10^8 ray-primitive pairs, ~3 s on two
// cores); all 10^5 under `make test-long` (docs/ACCURACY.md). Same tolerance
// and tie rule as bvh_trace_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "bvh_test_util.h"
#include "scene/load.h"
#include "support/test_scale.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

constexpr uint32_t RAY_COUNT = 100000;
// In CI, brute force tests at most this many ray-primitive pairs.
constexpr size_t BRUTE_FORCE_PAIRS = 100'000'000;

class BvhScene : public testing::TestWithParam<const char*> {};

TEST_P(BvhScene, GpuMatchesCpuTraversalAndBruteForce) {
    VKPATH_SKIP_WITHOUT_SHARED_SCENES();
    const scene::Scene s = scene::loadScene(test::sharedScene(GetParam()));
    const bvh::BvhBuild build = buildChecked(s);
    ASSERT_FALSE(build.primitives.empty());
    RecordProperty("primitives", static_cast<int>(build.primitives.size()));

    // Origins in the scene's box grown by a quarter on each side.
    const vec3 lo = build.nodes[0].boundsMin, hi = build.nodes[0].boundsMax;
    const vec3 margin = 0.25f * (hi - lo);
    const std::vector<Ray> rays = randomRays(build, RAY_COUNT, 51, lo - margin, hi + margin);

    GpuTracer tracer(test::context(), build);
    const std::vector<Hit> gpu = tracer.closest(rays);
    const shared::BvhView view{build.traversalNodes, build.primitives};
    std::vector<Hit> cpu(rays.size());
    parallelFor(rays.size(), [&](size_t i) { cpu[i] = view.bvhClosestHit(rays[i]); });
    const Comparison withCpu = compareHits(build, rays, gpu, cpu);
    EXPECT_EQ(withCpu.mismatches, 0u) << withCpu.first;
    EXPECT_GT(withCpu.hits, RAY_COUNT / 3);
    EXPECT_LE(withCpu.ties, RAY_COUNT / 1000);

    const size_t bruteCount = test::ciOrLong(
        std::min<size_t>(rays.size(), BRUTE_FORCE_PAIRS / build.primitives.size()), rays.size());
    const std::vector<Ray> subset(rays.begin(),
                                  rays.begin() + static_cast<std::ptrdiff_t>(bruteCount));
    const std::vector<Hit> gpuSubset(gpu.begin(),
                                     gpu.begin() + static_cast<std::ptrdiff_t>(bruteCount));
    const Comparison withBrute =
        compareHits(build, subset, gpuSubset, bruteForceClosest(build.primitives, subset));
    EXPECT_EQ(withBrute.mismatches, 0u) << withBrute.first;
    RecordProperty("brute_force_rays", static_cast<int>(bruteCount));

    const std::vector<uint32_t> occluded = tracer.occluded(rays);
    size_t wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i)
        wrong += occluded[i] != (cpu[i].primitive != VKP_NO_HIT ? 1u : 0u);
    EXPECT_EQ(wrong, 0u);
}

INSTANTIATE_TEST_SUITE_P(Scotty3d, BvhScene, testing::Values("bunny.dae", "CBspheres.dae"),
                         [](const testing::TestParamInfo<const char*>& p) {
                             std::string name = p.param;
                             return name.substr(0, name.find('.'));
                         });

}  // namespace
