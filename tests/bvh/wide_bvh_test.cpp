// The CPU reference's eight-wide tree (host/bvh/wide_bvh.h): collapsing makes
// each primitive part of exactly one wide leaf, a binary leaf or a binary
// subtree of at most LEAF_PRIMITIVES primitives with that node's box, copied
// into blocks of eight of one kind in leaf order, and traversal
// returns the binary traversal's hit bit for bit (t, primitive,
// barycentrics) and the same any-hit answer, on random rays and on rays aimed
// at the edges and vertices of closed meshes. Both must also equal brute force
// in leaf order exactly, primitive included: the rule for ties
// (shared/bvh_leaf.h) makes the hit at a shared distance the one of smallest
// leaf index, which is the one brute force keeps. Coincident triangles, tied
// on every ray that meets them, check that rule head on.
#include "bvh/wide_bvh.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <map>
#include <ostream>
#include <set>
#include <string>

#include "bvh_test_util.h"

namespace {

using namespace vkpath;
using namespace vkpath::test::bvh;

bool sameHit(const Hit& a, const Hit& b) {
    return std::memcmp(&a, &b, sizeof(Hit)) == 0;
}

struct Traced {
    size_t rays = 0, hits = 0, wideDiffers = 0, binaryDiffers = 0, bruteDiffers = 0,
           occlusionDiffers = 0;
};

// Traces every ray through both trees and brute force.
Traced traceAll(const bvh::BvhBuild& build, const std::vector<Ray>& rays) {
    const shared::BvhView view{build.traversalNodes, build.primitives};
    const bvh::WideBvh wide = bvh::collapseBvh(build);
    const std::vector<Hit> brute = bruteForceClosest(build.primitives, rays);
    Traced t;
    t.rays = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit binary = view.bvhClosestHit(rays[i]);
        const Hit wideHit = bvh::traceWide(view, wide, rays[i], false, 0u);
        t.hits += wideHit.primitive != VKP_NO_HIT;
        t.wideDiffers += !sameHit(wideHit, binary);
        t.binaryDiffers += !sameHit(binary, brute[i]);
        t.bruteDiffers += !sameHit(wideHit, brute[i]);
        const bool occluded = bvh::traceWide(view, wide, rays[i], true, 0u).primitive != VKP_NO_HIT;
        t.occlusionDiffers +=
            occluded != view.bvhOccluded(rays[i]) || occluded != (brute[i].primitive != VKP_NO_HIT);
    }
    return t;
}

void expectSameHits(const Traced& t) {
    EXPECT_EQ(t.wideDiffers, 0u) << "wide traversal differs from the binary one";
    EXPECT_EQ(t.binaryDiffers, 0u) << "binary traversal differs from brute force";
    EXPECT_EQ(t.bruteDiffers, 0u) << "wide traversal differs from brute force";
    EXPECT_EQ(t.occlusionDiffers, 0u) << "any-hit answers differ";
    EXPECT_GT(t.hits, t.rays / 4) << "too few hits for the comparison to mean much";
}

// The primitives of binary node `index`'s subtree, (first, count), for
// every node: a depth-first tree's subtree holds a contiguous range.
std::pair<uint32_t, uint32_t> subtreeRanges(
    const bvh::BvhBuild& build, uint32_t index,
    std::map<std::pair<uint32_t, uint32_t>, uint32_t>& nodeOfRange) {
    const shared::BvhNode& node = build.nodes[index];
    std::pair<uint32_t, uint32_t> range{node.offset, node.count};
    if (node.count == 0) {
        const auto left = subtreeRanges(build, index + 1, nodeOfRange);
        const auto right = subtreeRanges(build, node.offset, nodeOfRange);
        EXPECT_EQ(left.first + left.second, right.first);
        range = {left.first, left.second + right.second};
    }
    nodeOfRange[range] = index;
    return range;
}

// The leaf that `count` blocks from `first` hold, as (first primitive,
// count), after checking that they copy its primitives, triangles and
// spheres in blocks of their own, each kind in leaf order, eight to a block
// but the last of each kind.
std::pair<uint32_t, uint32_t> blockLeaf(const bvh::BvhBuild& build, const bvh::WideBvh& wide,
                                        uint32_t first, uint32_t count) {
    EXPECT_LE(first + count, wide.blocks.size());
    std::set<uint32_t> indices;
    for (uint32_t b = first; b < first + count && b < wide.blocks.size(); ++b) {
        const bvh::WideBvh::Block& block = wide.blocks[b];
        EXPECT_TRUE(block.triangles == 0 || block.spheres == 0)
            << "a block mixes triangles and spheres";
        const uint32_t used = block.triangles | block.spheres;
        EXPECT_NE(used, 0u);
        EXPECT_EQ(used & (used + 1), 0u) << "lanes in use are not the first ones";
        const bool last =
            b + 1 == first + count || ((wide.blocks[b + 1].spheres != 0) != (block.spheres != 0));
        if (!last) {
            EXPECT_EQ(used, (1u << bvh::WideBvh::BLOCK) - 1u)
                << "a block before its kind's last is not full";
        }
        for (uint32_t lane = 0; lane < bvh::WideBvh::BLOCK && (used >> lane & 1u); ++lane) {
            const uint32_t index = block.primitive[lane];
            if (lane > 0) {
                EXPECT_LT(block.primitive[lane - 1], index)
                    << "a block's lanes are not in leaf order";
            }
            EXPECT_TRUE(indices.insert(index).second)
                << "primitive " << index << " twice in a leaf";
            const BvhPrimitive& p = build.primitives.at(index);
            EXPECT_EQ((block.spheres >> lane & 1u) != 0, p.kind == VKP_PRIMITIVE_SPHERE);
            EXPECT_EQ(vec3(block.p0x[lane], block.p0y[lane], block.p0z[lane]), p.p0);
            EXPECT_EQ(vec3(block.p1x[lane], block.p1y[lane], block.p1z[lane]), p.p1);
            EXPECT_EQ(vec3(block.p2x[lane], block.p2y[lane], block.p2z[lane]), p.p2);
        }
    }
    if (indices.empty()) return {0, 0};
    EXPECT_EQ(*indices.rbegin() - *indices.begin() + 1, indices.size())
        << "a leaf's primitives are not a range";
    return {*indices.begin(), uint32_t(indices.size())};
}

// Checks the wide tree's structure against the binary tree it came from:
// each wide leaf is a binary leaf or a binary subtree of at most
// LEAF_PRIMITIVES primitives, with that node's box, and the wide leaves
// hold every primitive once.
void expectSoundCollapse(const bvh::BvhBuild& build) {
    const bvh::WideBvh wide = bvh::collapseBvh(build);
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> nodeOfRange;
    subtreeRanges(build, 0, nodeOfRange);
    std::vector<int> visits(wide.nodes.size(), 0);
    std::vector<int> covered(build.primitives.size(), 0);
    uint32_t deepest = 0;
    std::function<void(uint32_t, uint32_t)> walk = [&](uint32_t index, uint32_t depth) {
        ASSERT_LT(index, wide.nodes.size());
        ++visits[index];
        deepest = std::max(deepest, depth);
        const bvh::WideBvh::Node& node = wide.nodes[index];
        ASSERT_GE(node.children, 1u);
        ASSERT_LE(node.children, bvh::WideBvh::WIDTH);
        for (uint32_t i = 0; i < node.children; ++i) {
            EXPECT_LE(node.minX[i], node.maxX[i]);
            EXPECT_LE(node.minY[i], node.maxY[i]);
            EXPECT_LE(node.minZ[i], node.maxZ[i]);
            if (node.count[i] == 0) {
                walk(node.child[i], depth + 1);
                continue;
            }
            const auto range = blockLeaf(build, wide, node.child[i], node.count[i]);
            const auto binary = nodeOfRange.find(range);
            ASSERT_NE(binary, nodeOfRange.end()) << "a wide leaf is no binary subtree";
            const shared::BvhNode& b = build.nodes[binary->second];
            EXPECT_TRUE(b.count > 0 || range.second <= bvh::WideBvh::LEAF_PRIMITIVES);
            EXPECT_EQ(vec3(node.minX[i], node.minY[i], node.minZ[i]), b.boundsMin);
            EXPECT_EQ(vec3(node.maxX[i], node.maxY[i], node.maxZ[i]), b.boundsMax);
            for (uint32_t p = range.first; p < range.first + range.second; ++p) ++covered.at(p);
        }
    };
    walk(0, 0);
    for (size_t p = 0; p < covered.size(); ++p) EXPECT_EQ(covered[p], 1) << "primitive " << p;
    for (size_t i = 0; i < visits.size(); ++i)
        EXPECT_EQ(visits[i], 1) << "wide node " << i << " reached " << visits[i] << " times";
    EXPECT_LE(deepest, build.stats.maxDepth);
}

TEST(WideBvh, CollapseKeepsEveryLeafOnce) {
    for (const auto& [triangles, spheres] :
         {std::pair{1u, 0u}, {3u, 0u}, {0u, 9u}, {1000u, 0u}, {600u, 300u}}) {
        SCOPED_TRACE(fmt::format("{} triangles, {} spheres", triangles, spheres));
        scene::Scene s = emptyScene();
        if (triangles) addTriangleSoup(s, triangles, 0.15f, 11);
        if (spheres) addSphereField(s, spheres, 0.01f, 0.08f, 12);
        expectSoundCollapse(buildChecked(s));
    }
    // Leaves of one primitive (the deepest trees, the most nodes to open) and
    // of up to 16 (several blocks each).
    for (const uint32_t leaf : {1u, 15u}) {
        SCOPED_TRACE(fmt::format("leaves of at most {}", leaf));
        scene::Scene s = emptyScene();
        addTriangleSoup(s, 500, 0.15f, 13);
        addSphereField(s, 100, 0.01f, 0.08f, 14);
        expectSoundCollapse(buildChecked(s, bvh::BvhOptions{.maxLeafSize = leaf}));
    }
}

TEST(WideBvh, EmptyTreeHitsNothing) {
    const bvh::BvhBuild build = buildChecked(emptyScene());
    const bvh::WideBvh wide = bvh::collapseBvh(build);
    EXPECT_TRUE(wide.nodes.empty());
    const shared::BvhView view{build.traversalNodes, build.primitives};
    EXPECT_EQ(bvh::traceWide(view, wide, makeRay(vec3(0.0f), vec3(0.0f, 0.0f, 1.0f)), false, 0u)
                  .primitive,
              VKP_NO_HIT);
}

TEST(WideBvh, RandomRaysHitWhatTheBinaryTreeHits) {
    for (const auto& [triangles, spheres] : {std::pair{1000u, 0u}, {0u, 800u}, {600u, 300u}}) {
        SCOPED_TRACE(fmt::format("{} triangles, {} spheres", triangles, spheres));
        scene::Scene s = emptyScene();
        if (triangles) addTriangleSoup(s, triangles, 0.15f, 11);
        if (spheres) addSphereField(s, spheres, 0.01f, 0.08f, 12);
        for (const uint32_t leaf : {4u, 15u}) {
            const bvh::BvhBuild build = buildChecked(s, bvh::BvhOptions{.maxLeafSize = leaf});
            expectSameHits(traceAll(build, randomRays(build, 20000, 31)));
        }
    }
}

// Rays through shared edges and vertices meet two or more triangles, often
// at exactly the same distance.
TEST(WideBvh, RaysAtEdgesAndVerticesHitWhatTheBinaryTreeHits) {
    for (const scene::Mesh& mesh : {icosphere(4, 1.0f, vec3(0.0f)), tessellatedCube(24)}) {
        SCOPED_TRACE(mesh.name);
        scene::Scene s = emptyScene();
        s.meshes.push_back(mesh);
        const bvh::BvhBuild build = buildChecked(s);
        expectSameHits(traceAll(build, raysAtEdgesAndVertices(s.meshes[0], 20000, 41).rays));
    }
}

// Every triangle twice, in leaves of one primitive so that each lies in a
// leaf of its own: every ray that meets one meets its twin at the same
// distance, and the two trees visit twins in different orders.
TEST(WideBvh, CoincidentTrianglesGiveTheSmallerLeafIndex) {
    scene::Scene s = emptyScene();
    addTriangleSoup(s, 400, 0.15f, 17);
    s.meshes.push_back(s.meshes[0]);
    const bvh::BvhBuild build = buildChecked(s, bvh::BvhOptions{.maxLeafSize = 1});
    const std::vector<Ray> rays = randomRays(build, 20000, 43);
    const Traced t = traceAll(build, rays);
    expectSameHits(t);
}

}  // namespace
