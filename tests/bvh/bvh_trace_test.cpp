// Closest-hit and any-hit traversal against brute force: 10^5 random rays per
// scene, traced by the GPU kernels through the BVH, must find what testing
// every primitive on the CPU finds.
//
// Equality: the same primitive with t within 1e-5 relative (the GPU may round
// a division differently). Ties: when two primitives are hit at the same
// distance (to 1e-5), either may be reported; such a ray counts as a tie when
// the CPU confirms that the reported primitive is hit within the tolerance of
// the brute-force distance. Random soups and fields produce almost none.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>

#include "bvh_test_util.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

constexpr uint32_t RAY_COUNT = 100000;

struct TraceCase {
    const char* name;
    uint32_t triangles;
    uint32_t spheres;
};

// Names the case in test listings (instead of its bytes).
void PrintTo(const TraceCase& c, std::ostream* os) {
    *os << c.name;
}

class BvhTrace : public testing::TestWithParam<TraceCase> {};

scene::Scene makeScene(const TraceCase& c) {
    scene::Scene s = emptyScene();
    if (c.triangles) addTriangleSoup(s, c.triangles, 0.15f, 11);
    if (c.spheres) addSphereField(s, c.spheres, 0.01f, 0.08f, 12);
    return s;
}

// The GPU kernels, specialised to the tree's depth as a render's are, on
// RAY_COUNT random rays.
void expectGpuMatchesBruteForce(const bvh::BvhBuild& build) {
    const std::vector<Ray> rays = randomRays(build, RAY_COUNT, 21);
    const std::vector<Hit> expected = bruteForceClosest(build.primitives, rays);

    GpuTracer tracer(test::context(), build);
    const std::vector<Hit> gpu = tracer.closest(rays);
    const Comparison c = compareHits(build, rays, gpu, expected);
    EXPECT_EQ(c.mismatches, 0u) << c.first;
    EXPECT_GT(c.hits, RAY_COUNT / 3) << "too few hits for the comparison to mean much";
    EXPECT_LE(c.ties, RAY_COUNT / 10000) << "more ties than random geometry should give";
    testing::Test::RecordProperty("ties", static_cast<int>(c.ties));

    // Any hit over the full ray: occluded exactly when brute force hits.
    const std::vector<uint32_t> occluded = tracer.occluded(rays);
    size_t wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i)
        wrong += occluded[i] != (expected[i].primitive != VKP_NO_HIT ? 1u : 0u);
    EXPECT_EQ(wrong, 0u);
}

TEST_P(BvhTrace, GpuClosestAndAnyHitMatchBruteForce) {
    const bvh::BvhBuild build = buildChecked(makeScene(GetParam()));
    expectGpuMatchesBruteForce(build);
}

// A tree no deeper than VKP_BVH_SHALLOW_DEPTH is traversed with its whole
// stack in eight variables (shared/bvh_traverse.h): here one held to that
// depth over as many primitives as fit (2^8; the builder's guard splits down
// to single primitives), so that rays fill every level, against brute force.
TEST(BvhTraceStack, TheStackInVariablesAtItsFullDepth) {
    const scene::Scene s = makeScene({"Mixed", 170, 86});
    const bvh::BvhBuild deep = buildChecked(s);
    EXPECT_GT(deep.stats.maxDepth, VKP_BVH_SHALLOW_DEPTH);
    EXPECT_EQ(bvh::traversalFeatures(deep), VKP_FEATURE_DEEP_BVH);

    const bvh::BvhBuild shallow = buildChecked(s, {.maxDepth = VKP_BVH_SHALLOW_DEPTH});
    ASSERT_EQ(shallow.stats.maxDepth, VKP_BVH_SHALLOW_DEPTH);
    ASSERT_EQ(bvh::traversalFeatures(shallow), 0u);
    expectGpuMatchesBruteForce(shallow);
}

TEST_P(BvhTrace, CpuTraversalMatchesBruteForceExactly) {
    // The same shared code on the CPU: bit-identical t, and the same primitive
    // (at exactly the same distance the smaller leaf index, shared/bvh_leaf.h,
    // which brute force in leaf order keeps too).
    const scene::Scene s = makeScene(GetParam());
    const bvh::BvhBuild build = buildChecked(s);
    const std::vector<Ray> rays = randomRays(build, RAY_COUNT / 4, 22);
    const std::vector<Hit> expected = bruteForceClosest(build.primitives, rays);
    const shared::BvhView view{build.traversalNodes, build.primitives};
    size_t mismatches = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit h = view.bvhClosestHit(rays[i]);
        if (h.t != expected[i].t || h.primitive != expected[i].primitive) ++mismatches;
        const bool occluded = view.bvhOccluded(rays[i]);
        if (occluded != (expected[i].primitive != VKP_NO_HIT)) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0u);
}

// A deeper tree's stack spills below its top eight entries to an array and
// refills from it. Thin beads strung along x, each at its own place in a
// 2 x 2 cross-section (so the heuristic splits along the row): a ray along
// the row crosses both boxes of every level above the beads' own, so the
// stack grows by one per level, past eight, and the bead it hits lies about
// a thousand beads on, in a subtree pushed near the root and refilled from
// the array.
TEST(BvhTraceStack, TheStackSpillsPastEightEntriesAndRefills) {
    constexpr int COUNT = 4096;
    constexpr float RADIUS = 0.036f;  // a ray meets pi r^2 / 4 = 1/1000 of the beads
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> across(-1.0f, 1.0f);
    scene::Scene s = emptyScene();
    for (int i = 0; i < COUNT; ++i)
        s.spheres.push_back(
            {.name = "bead", .center = vec3(float(i), across(rng), across(rng)), .radius = RADIUS});
    const bvh::BvhBuild build = buildChecked(s);
    ASSERT_GE(build.stats.maxDepth, VKP_BVH_SHALLOW_DEPTH + 3) << "the stack would not spill";
    ASSERT_EQ(bvh::traversalFeatures(build), VKP_FEATURE_DEEP_BVH);

    std::vector<Ray> rays;
    for (int i = 0; i < 4000; ++i) {
        const float y = across(rng), z = across(rng);
        rays.push_back(i % 2 ? makeRay(vec3(-5, y, z), vec3(1, 0, 0))
                             : makeRay(vec3(COUNT + 5, y, z), vec3(-1, 0, 0)));
    }
    const std::vector<Hit> expected = bruteForceClosest(build.primitives, rays);
    GpuTracer tracer(test::context(), build);
    const Comparison c = compareHits(build, rays, tracer.closest(rays), expected);
    EXPECT_EQ(c.mismatches, 0u) << c.first;
    EXPECT_GT(c.hits, rays.size() / 2);
    const std::vector<uint32_t> occluded = tracer.occluded(rays);
    size_t wrong = 0;
    for (size_t i = 0; i < rays.size(); ++i)
        wrong += occluded[i] != (expected[i].primitive != VKP_NO_HIT ? 1u : 0u);
    EXPECT_EQ(wrong, 0u);

    // The same code on the CPU, exactly.
    const shared::BvhView view{build.traversalNodes, build.primitives};
    size_t cpuMismatches = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit h = view.bvhClosestHit(rays[i]);
        cpuMismatches += h.t != expected[i].t || h.primitive != expected[i].primitive;
    }
    EXPECT_EQ(cpuMismatches, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BvhTrace,
    testing::Values(TraceCase{"TriangleSoup", 1000, 0}, TraceCase{"SphereField", 0, 800},
                    TraceCase{"Mixed", 600, 300}, TraceCase{"SmallMixed", 24, 16}),
    [](const testing::TestParamInfo<TraceCase>& p) { return std::string(p.param.name); });

}  // namespace
