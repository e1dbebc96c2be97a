// The traversal's node records (host/bvh/traversal_nodes.h, layout in
// shaders/shared/bvh.h): the child words carried in the boxes' low bits, and
// boxes that still hold what the tree's boxes hold. Traversal itself (GPU and
// CPU through these records, against brute force) is tested in
// bvh_trace_test.cpp, bvh_robustness_test.cpp and the scene tests.
#include "bvh/traversal_nodes.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "bvh_test_util.h"

namespace vkpath::test::bvh {
namespace {

using shared::BvhNode;
using vkpath::bvh::BvhBuild;
using vkpath::bvh::embedAbove;
using vkpath::bvh::embedBelow;
using vkpath::bvh::packTraversalNodes;

// Distance in ulps between two finite floats of one sign.
int64_t ulps(float a, float b) {
    return std::abs(int64_t(std::bit_cast<uint32_t>(a) & 0x7fffffffu) -
                    int64_t(std::bit_cast<uint32_t>(b) & 0x7fffffffu));
}

TEST(BvhTraversalNodes, EmbeddedBoundsMoveOutwardAndCarryTheirBits) {
    const float denormal = std::numeric_limits<float>::denorm_min() * 5.0f;
    for (float x : {0.0f, -0.0f, denormal, -denormal, 1e-31f, 1.0f, -1.0f, 1e-30f, -3.5e4f, 1e5f,
                    7.25e-5f, 0.75f, -2.0f, 3e38f, -3e38f}) {
        for (uint32_t bits = 0; bits < 64; ++bits) {
            SCOPED_TRACE(::testing::Message() << "x " << x << ", bits " << bits);
            const float below = embedBelow(x, bits), above = embedAbove(x, bits);
            EXPECT_TRUE(std::isfinite(below) && std::isfinite(above));
            EXPECT_LE(below, x);
            EXPECT_GE(above, x);
            EXPECT_EQ(std::bit_cast<uint32_t>(below) & 63u, bits);
            EXPECT_EQ(std::bit_cast<uint32_t>(above) & 63u, bits);
            // Normal, and within 127 ulps of x (of +-2^-100 for a smaller x).
            EXPECT_GE(std::abs(below), 0x1p-101f);
            EXPECT_GE(std::abs(above), 0x1p-101f);
            if (std::abs(x) >= 0x1p-100f) {
                if ((below < 0.0f) == (x < 0.0f)) {
                    EXPECT_LE(ulps(below, x), 127);
                }
                if ((above < 0.0f) == (x < 0.0f)) {
                    EXPECT_LE(ulps(above, x), 127);
                }
            }
        }
    }
    EXPECT_THROW(embedAbove(std::numeric_limits<float>::max(), 0), std::length_error);
    EXPECT_THROW(embedBelow(std::numeric_limits<float>::infinity(), 0), std::length_error);
}

struct Child {
    glm::vec3 min, max;
    uint32_t word;
};

// Child 0 or 1 of the record at `texel`, read as the traversal reads it.
Child readChild(const std::vector<glm::uvec4>& texels, uint32_t texel, int which) {
    uint32_t w[12];
    for (int t = 0; t < 3; ++t)
        for (int c = 0; c < 4; ++c) w[4 * t + c] = texels.at(texel + t)[c];
    const uint32_t* b = w + 6 * which;
    const glm::uvec3 lo(b[0], b[1], b[2]), hi(b[3], b[4], b[5]);
    return {glm::vec3(std::bit_cast<float>(lo.x), std::bit_cast<float>(lo.y),
                      std::bit_cast<float>(lo.z)),
            glm::vec3(std::bit_cast<float>(hi.x), std::bit_cast<float>(hi.y),
                      std::bit_cast<float>(hi.z)),
            shared::bvhChildWord(lo, hi)};
}

// Walks the tree and its records together: every child word names the
// child's record (interior) or its primitive range (leaf), and every record's
// box holds the tree's box of that child. Returns the records reached.
size_t expectRecordsMatchTree(const BvhBuild& build) {
    const auto& nodes = build.nodes;
    size_t reached = 0;
    std::vector<std::pair<uint32_t, uint32_t>> todo{{0u, 0u}};  // (tree node, record texel)
    while (!todo.empty()) {
        const auto [node, texel] = todo.back();
        todo.pop_back();
        ++reached;
        const uint32_t children[2] = {node + 1, nodes[node].offset};
        for (int which = 0; which < 2; ++which) {
            const BvhNode& tree = nodes[children[which]];
            const Child c = readChild(build.traversalNodes, texel, which);
            EXPECT_TRUE(glm::all(glm::lessThanEqual(c.min, tree.boundsMin)))
                << "node " << children[which];
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(c.max, tree.boundsMax)))
                << "node " << children[which];
            const uint32_t count = c.word >> VKP_BVH_WORD_COUNT_SHIFT;
            EXPECT_EQ(count, tree.count) << "node " << children[which];
            if (tree.count != 0) {
                EXPECT_EQ(c.word & VKP_BVH_WORD_INDEX_MASK, tree.offset);
            } else {
                todo.emplace_back(children[which], c.word & VKP_BVH_WORD_INDEX_MASK);
            }
        }
    }
    return reached;
}

TEST(BvhTraversalNodes, RecordsHoldTheTreesChildrenAndBoxes) {
    scene::Scene mixed = emptyScene();
    addTriangleSoup(mixed, 3000, 0.1f, 1);
    addSphereField(mixed, 500, 0.005f, 0.05f, 2);
    mixed.meshes.push_back(icosphere(3, 0.5f, vec3(0.2f, 0.1f, -0.3f)));
    scene::Scene far = emptyScene();
    far.meshes.push_back(
        icosphere(2, 2.0f, vec3(1e5f, -1e5f, 3e4f)));  // small and far from the origin
    for (const auto* s : {&mixed, &far}) {
        for (uint32_t leaf : {1u, 4u, 15u}) {
            const BvhBuild build = buildChecked(*s, {.maxLeafSize = leaf});
            ASSERT_GT(build.nodes.size(), 1u);
            size_t interior = 0;
            for (const BvhNode& n : build.nodes) interior += n.count == 0 ? 1 : 0;
            EXPECT_EQ(build.traversalNodes.size(), VKP_BVH_RECORD_TEXELS * interior);
            EXPECT_EQ(expectRecordsMatchTree(build), interior);
        }
    }
}

TEST(BvhTraversalNodes, ASingleLeafAndTheEmptyTree) {
    scene::Scene one = emptyScene();
    addSphereField(one, 1, 0.1f, 0.2f, 7);
    const BvhBuild leaf = buildChecked(one);
    ASSERT_EQ(leaf.nodes.size(), 1u);
    ASSERT_EQ(leaf.traversalNodes.size(), VKP_BVH_RECORD_TEXELS);
    for (int which = 0; which < 2; ++which) {
        const Child c = readChild(leaf.traversalNodes, 0, which);
        EXPECT_EQ(c.word, (1u << VKP_BVH_WORD_COUNT_SHIFT) | 0u);
        EXPECT_TRUE(glm::all(glm::lessThanEqual(c.min, leaf.nodes[0].boundsMin)));
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(c.max, leaf.nodes[0].boundsMax)));
    }
    // Traversal tests the leaf (twice) and finds the sphere.
    const shared::BvhView leafView{leaf.traversalNodes, leaf.primitives};
    const vec3 centre = leaf.primitives[0].p0;
    EXPECT_EQ(
        leafView.bvhClosestHit(makeRay(centre - vec3(0.0f, 0.0f, 5.0f), vec3(0.0f, 0.0f, 1.0f)))
            .primitive,
        0u);
    EXPECT_TRUE(
        leafView.bvhOccluded(makeRay(centre - vec3(0.0f, 0.0f, 5.0f), vec3(0.0f, 0.0f, 1.0f))));
    EXPECT_EQ(
        leafView.bvhClosestHit(makeRay(centre - vec3(0.0f, 0.0f, 5.0f), vec3(0.0f, 1.0f, 0.0f)))
            .primitive,
        VKP_NO_HIT);

    const BvhBuild empty = buildChecked(emptyScene());
    ASSERT_EQ(empty.traversalNodes.size(), VKP_BVH_RECORD_TEXELS);
    for (int which = 0; which < 2; ++which) {
        const Child c = readChild(empty.traversalNodes, 0, which);
        EXPECT_TRUE(std::isnan(c.min.x) && std::isnan(c.max.z));
    }
    // No ray enters a box of NaN: the CPU traversal of the empty tree ends at once.
    const shared::BvhView view{empty.traversalNodes, empty.primitives};
    EXPECT_EQ(view.bvhClosestHit(makeRay(vec3(0.0f), vec3(0.0f, 0.0f, 1.0f))).primitive,
              VKP_NO_HIT);
}

TEST(BvhTraversalNodes, WhatAWordCannotHoldIsRefused) {
    // A hand-made tree whose leaf is longer than a word's count.
    BvhNode root{glm::vec3(0.0f), 0u, glm::vec3(1.0f), 0u};
    root.offset = 2;
    const BvhNode small{glm::vec3(0.0f), 0u, glm::vec3(1.0f), 1u};
    BvhNode big{glm::vec3(0.0f), 1u, glm::vec3(1.0f), VKP_BVH_MAX_LEAF_COUNT + 1};
    const std::vector<BvhNode> tooLong{root, small, big};
    EXPECT_THROW(packTraversalNodes(tooLong), std::length_error);
    big.count = 1;
    big.offset = VKP_BVH_WORD_INDEX_MASK + 1;
    const std::vector<BvhNode> farOffset{root, small, big};
    EXPECT_THROW(packTraversalNodes(farOffset), std::length_error);
    big.offset = 1;
    const std::vector<BvhNode> fine{root, small, big};
    EXPECT_EQ(packTraversalNodes(fine).size(), VKP_BVH_RECORD_TEXELS);
}

}  // namespace
}  // namespace vkpath::test::bvh
