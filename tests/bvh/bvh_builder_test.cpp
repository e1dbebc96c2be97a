// The builder: integrity on varied scenes and options, determinism whatever the
// thread count, the depth bound the traversal stack relies on, the integrity
// check's own ability to fail, and the storage-buffer limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "bvh_test_util.h"
#include "input_error.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;
using bvh::BvhBuild;
using bvh::BvhOptions;

scene::Scene mixedScene() {
    scene::Scene s = emptyScene();
    addTriangleSoup(s, 3000, 0.1f, 1);
    addSphereField(s, 500, 0.005f, 0.05f, 2);
    s.meshes.push_back(icosphere(3, 0.5f, vec3(0.2f, 0.1f, -0.3f)));
    return s;
}

bool identical(const BvhBuild& a, const BvhBuild& b) {
    return a.nodes.size() == b.nodes.size() && a.primitives.size() == b.primitives.size() &&
           std::memcmp(a.nodes.data(), b.nodes.data(), a.nodeBytes()) == 0 &&
           std::memcmp(a.primitives.data(), b.primitives.data(), a.primitiveBytes()) == 0 &&
           a.traversalNodes == b.traversalNodes;
}

TEST(BvhBuilder, IntegrityAcrossScenesAndOptions) {
    std::vector<std::pair<std::string, scene::Scene>> scenes;
    scenes.emplace_back("mixed", mixedScene());
    {
        // Every centroid in one point: binning cannot split, the median must.
        scene::Scene s = emptyScene();
        scene::Mesh m;
        m.name = "stack";
        m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        for (int i = 0; i < 500; ++i) m.triangles.emplace_back(0, 1, 2);
        s.meshes.push_back(m);
        for (int i = 0; i < 100; ++i)
            s.spheres.push_back(scene::Sphere{.name = "same", .center = {3, 3, 3}, .radius = 0.5f});
        scenes.emplace_back("coincident", s);
    }
    {
        scene::Scene s = emptyScene();
        s.spheres.push_back(scene::Sphere{.name = "one", .center = {1, 2, 3}, .radius = 0.25f});
        scenes.emplace_back("single", s);
    }
    {
        // Flat: every triangle in the plane z = 0 (boxes of zero thickness).
        scene::Scene s = emptyScene();
        scene::Mesh m = tessellatedCube(8);
        std::erase_if(m.triangles, [&](const glm::uvec3& t) {
            return m.positions[t.x].z != 1.0f || m.positions[t.y].z != 1.0f ||
                   m.positions[t.z].z != 1.0f;
        });
        s.meshes.push_back(m);
        scenes.emplace_back("flat", s);
    }
    const BvhOptions options[] = {{},
                                  {.maxLeafSize = 1},
                                  {.maxLeafSize = 8, .binCount = 12},
                                  {.maxLeafSize = 15, .binCount = 32},
                                  {.maxLeafSize = 2, .binCount = 2, .traversalCost = 0.25f}};
    for (const auto& [name, s] : scenes) {
        for (const BvhOptions& o : options) {
            SCOPED_TRACE(name + ", max leaf " + std::to_string(o.maxLeafSize) + ", bins " +
                         std::to_string(o.binCount));
            const BvhBuild build = buildChecked(s, o);
            EXPECT_LE(build.stats.largestLeaf, o.maxLeafSize);
            EXPECT_LE(build.stats.maxDepth, static_cast<uint32_t>(VKP_BVH_MAX_DEPTH));
            EXPECT_EQ(build.stats.nodes, build.nodes.size());
            EXPECT_EQ(build.stats.leaves * 2 - 1, build.nodes.size()) << "a binary tree";
            EXPECT_EQ(build.primitives.size(), build.stats.triangles + build.stats.spheres);
            EXPECT_GE(build.stats.sahCost, 0.0);
        }
    }
}

TEST(BvhBuilder, EmptySceneGivesAnEmptyTreeThatNothingHits) {
    const scene::Scene s = emptyScene();
    const BvhBuild build = buildChecked(s);
    ASSERT_EQ(build.nodes.size(), 1u);
    EXPECT_EQ(build.nodes[0].count, 0u);
    EXPECT_EQ(build.nodes[0].offset, 0u);
    EXPECT_TRUE(build.primitives.empty());
    GpuTracer tracer(test::context(), build);
    const std::vector<Ray> rays = {makeRay(vec3(0.0f), vec3(0, 0, 1)),
                                   makeRay(vec3(1.0f), vec3(-1, 0, 0))};
    for (const Hit& h : tracer.closest(rays)) EXPECT_EQ(h.primitive, VKP_NO_HIT);
    for (uint32_t o : tracer.occluded(rays)) EXPECT_EQ(o, 0u);
}

TEST(BvhBuilder, DeterministicWhateverTheThreads) {
    const scene::Scene s = mixedScene();
    const BvhBuild serial = buildChecked(s, {.threads = 1});
    const BvhBuild again = buildChecked(s, {.threads = 1});
    EXPECT_TRUE(identical(serial, again));
    for (uint32_t threads : {2u, 3u, 8u}) {
        SCOPED_TRACE(threads);
        // A low threshold hands out many subtrees.
        const BvhBuild parallel = buildChecked(s, {.threads = threads, .parallelThreshold = 64});
        EXPECT_TRUE(identical(serial, parallel));
    }
}

TEST(BvhBuilder, LargeMeshBuildsInParallelIdentically) {
    scene::Scene s = emptyScene();
    s.meshes.push_back(icosphere(6, 1.0f, vec3(0.0f)));  // 81920 triangles
    const BvhBuild serial = buildChecked(s, {.threads = 1});
    const BvhBuild parallel = buildChecked(s, {.threads = 2});
    EXPECT_TRUE(identical(serial, parallel));
    EXPECT_EQ(parallel.stats.triangles, 81920u);
    RecordProperty("serial_ms", std::to_string(serial.stats.buildMilliseconds));
    RecordProperty("parallel_ms", std::to_string(parallel.stats.buildMilliseconds));
}

// Primitives spaced geometrically make the SAH peel one off at a time, the
// deepest tree it can build; the guard must keep leaves within maxDepth.
scene::Scene geometricChain(int count) {
    scene::Scene s = emptyScene();
    scene::Mesh m;
    m.name = "chain";
    for (int i = 0; i < count; ++i) {
        const float x = std::ldexp(1.0f, i);  // 2^i
        const auto base = static_cast<uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(),
                           {{x, 0, 0}, {x + 0.01f * x, 0, 0}, {x, 0.01f * x, 0}});
        m.triangles.emplace_back(base, base + 1, base + 2);
    }
    s.meshes.push_back(m);
    return s;
}

TEST(BvhBuilder, DepthStaysWithinTheTraversalStack) {
    // 60 triangles at x = 2^i: the SAH alone builds a deep, lopsided tree.
    const scene::Scene s = geometricChain(60);
    const BvhBuild unbounded = buildChecked(s);
    EXPECT_LE(unbounded.stats.maxDepth, static_cast<uint32_t>(VKP_BVH_MAX_DEPTH));
    EXPECT_GT(unbounded.stats.maxDepth, 12u) << "the limits below would not bind";
    RecordProperty("unbounded_depth", static_cast<int>(unbounded.stats.maxDepth));
    for (uint32_t limit : {6u, 9u, 12u}) {
        SCOPED_TRACE(limit);
        const BvhBuild bounded = buildChecked(s, {.maxDepth = limit});
        EXPECT_LE(bounded.stats.maxDepth, limit);
    }
    // Nothing is lost to the guard: the deep tree still finds every triangle.
    const BvhBuild bounded = buildChecked(s, {.maxDepth = 6});
    const shared::BvhView view{bounded.traversalNodes, bounded.primitives};
    for (const shared::BvhPrimitive& p : bounded.primitives) {
        const vec3 target = (p.p0 + p.p1 + p.p2) / 3.0f;
        const Hit h = view.bvhClosestHit(makeRay(target + vec3(0, 0, 1), vec3(0, 0, -1)));
        ASSERT_NE(h.primitive, VKP_NO_HIT);
        EXPECT_EQ(bounded.primitives[h.primitive].id, p.id);
    }
    EXPECT_THROW(bvh::buildBvh(s, {.maxDepth = 5}), std::invalid_argument)
        << "60 primitives need depth 6";
}

TEST(BvhBuilder, IntegrityCheckFindsCorruption) {
    const scene::Scene s = mixedScene();
    const BvhBuild good = buildChecked(s);
    ASSERT_GT(good.nodes.size(), 3u);
    auto problems = [&](const BvhBuild& b) { return bvh::integrityCheck(b, s); };

    BvhBuild b = good;
    b.nodes[1].boundsMax.x =
        good.nodes[0].boundsMax.x + 1.0f;  // a child sticking out of its parent
    EXPECT_FALSE(problems(b).empty());

    b = good;
    b.primitives[1] = b.primitives[0];  // one primitive twice, another missing
    EXPECT_FALSE(problems(b).empty());

    b = good;
    b.primitives[5].p1.y += 0.5f;  // data that no longer matches the scene (or its leaf box)
    EXPECT_FALSE(problems(b).empty());

    b = good;
    for (auto& n : b.nodes)
        if (n.count > 1) {
            n.count -= 1;  // a primitive in no leaf
            break;
        }
    EXPECT_FALSE(problems(b).empty());

    b = good;
    b.nodes[0].offset = 1;  // the second child is the first: not a tree in preorder
    EXPECT_FALSE(problems(b).empty());

    b = good;
    b.primitives.pop_back();
    EXPECT_FALSE(problems(b).empty());
}

TEST(BvhBuilder, BadInputAndOptionsAreRejected) {
    scene::Scene s = emptyScene();
    scene::Mesh m;
    m.name = "broken";
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 3}};
    s.meshes.push_back(m);
    EXPECT_THROW(bvh::buildBvh(s), InputError);
    const scene::Scene ok = mixedScene();
    EXPECT_THROW(bvh::buildBvh(ok, {.maxLeafSize = 0}), std::invalid_argument);
    EXPECT_THROW(bvh::buildBvh(ok, {.maxLeafSize = VKP_BVH_MAX_LEAF_COUNT + 1}),
                 std::invalid_argument);
    EXPECT_THROW(bvh::buildBvh(ok, {.binCount = 1}), std::invalid_argument);
    EXPECT_THROW(bvh::buildBvh(ok, {.binCount = 257}), std::invalid_argument);
    EXPECT_THROW(bvh::buildBvh(ok, {.maxDepth = VKP_BVH_MAX_DEPTH + 1}), std::invalid_argument);
}

TEST(BvhBuilder, PaddingIsOutwardAndMonotone) {
    for (float x : {0.0f, -0.0f, 1.0f, -1.0f, 1e-30f, -3.5e4f, 1e5f, 7.25e-5f, 3e38f}) {
        EXPECT_LT(bvh::padBelow(x), x);
        EXPECT_GT(bvh::padAbove(x), x);
        const float next = std::nextafter(x, std::numeric_limits<float>::infinity());
        EXPECT_LE(bvh::padAbove(x), bvh::padAbove(next));
        EXPECT_LE(bvh::padBelow(x), bvh::padBelow(next));
    }
}

TEST(BvhBuilder, UploadReportsItsMemory) {
    const scene::Scene s = mixedScene();
    const BvhBuild build = buildChecked(s);
    const auto extents = bvh::arrayExtents(build);
    EXPECT_EQ(extents[0].bytes, build.traversalNodeBytes());
    EXPECT_EQ(extents[0].count, build.traversalNodes.size());
    EXPECT_EQ(extents[1].bytes, build.primitiveBytes());
    EXPECT_EQ(extents[1].count, build.primitives.size());
    // A limit one byte below the larger array sends the scene to the address path.
    const uint64_t larger = std::max(build.traversalNodeBytes(), build.primitiveBytes());
    EXPECT_TRUE(vk::chooseAddressAccess(extents, vk::BufferLimits{larger - 1, larger}));
    EXPECT_FALSE(vk::chooseAddressAccess(extents, vk::BufferLimits{larger, larger}));
    EXPECT_THROW(vk::chooseAddressAccess(extents, vk::BufferLimits{larger - 1, larger - 1}),
                 InputError);

    for (bool byAddress : {false, true}) {
        const bvh::GpuBvh gpu = bvh::uploadBvh(test::context(), build, byAddress);
        EXPECT_EQ(gpu.bytes(), build.bytes());
        EXPECT_EQ(gpu.nodes.download<glm::uvec4>(), build.traversalNodes);
        EXPECT_EQ(&gpu.nodeBinding() == &gpu.nodes, !byAddress);
        EXPECT_EQ(gpu.addresses().nodes != glm::uvec2(0), byAddress);
    }
    const std::string line = bvh::describeMemory(build);
    EXPECT_NE(line.find(std::to_string(build.nodes.size()) + " nodes"), std::string::npos) << line;
    EXPECT_NE(line.find(std::to_string(build.primitives.size()) + " primitives"), std::string::npos)
        << line;
}

}  // namespace
