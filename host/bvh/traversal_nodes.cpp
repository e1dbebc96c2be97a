#include "bvh/traversal_nodes.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <stdexcept>

#include "bvh/parallel_chunks.h"

namespace vkpath::bvh {

namespace {

using shared::BvhNode;

constexpr uint32_t WORD_MASK = (1u << VKP_BVH_WORD_BITS) - 1u;
constexpr uint32_t MAGNITUDE_MASK = 0x7fffffffu;
constexpr uint32_t LARGEST_FINITE = 0x7f7fffffu;  // FLT_MAX's bits
constexpr float TINY = 0x1p-100f;

// The magnitude (bits of |result|) nearest `magnitude` with low bits `bits`,
// not above it (down) or not below it (up).
uint32_t magnitudeWith(uint32_t magnitude, uint32_t bits, bool down) {
    uint32_t m = (magnitude & ~WORD_MASK) | bits;
    if (down && m > magnitude) m -= WORD_MASK + 1u;
    if (!down && m < magnitude) m += WORD_MASK + 1u;
    if (m > LARGEST_FINITE)
        throw std::length_error(
            fmt::format("BVH: a bound of magnitude {} is too close to the largest float",
                        std::bit_cast<float>(magnitude)));
    return m;
}

// Below (toward -infinity) or above, with low bits `bits`.
float embed(float x, uint32_t bits, bool below) {
    if (!std::isfinite(x)) throw std::length_error("BVH: a bound is not finite");
    if (!(std::abs(x) >= TINY)) x = below ? -TINY : TINY;
    const uint32_t u = std::bit_cast<uint32_t>(x);
    const uint32_t sign = u & ~MAGNITUDE_MASK;
    // For a positive x a smaller value is a smaller magnitude; for a negative, a larger.
    const bool down = below == (sign == 0u);
    return std::bit_cast<float>(sign | magnitudeWith(u & MAGNITUDE_MASK, bits, down));
}

uint32_t childWord(std::span<const BvhNode> nodes, uint32_t child,
                   const std::vector<uint32_t>& record) {
    const BvhNode& n = nodes[child];
    if (n.count == 0) return record[child];
    if (n.count > VKP_BVH_MAX_LEAF_COUNT)
        throw std::length_error(
            fmt::format("BVH: a leaf of {} primitives, more than the {} a node word holds", n.count,
                        VKP_BVH_MAX_LEAF_COUNT));
    if (n.offset > VKP_BVH_WORD_INDEX_MASK)
        throw std::length_error(
            fmt::format("BVH: primitive {} is past the 2^28 a node word indexes", n.offset));
    return (n.count << VKP_BVH_WORD_COUNT_SHIFT) | n.offset;
}

// A child's box with its word in the low bits: six floats, min.xyz max.xyz.
void putChild(const BvhNode& child, uint32_t word, uint32_t* out) {
    auto bitsOf = [word](uint32_t slot) {
        return (word >> (VKP_BVH_WORD_BITS * slot)) & WORD_MASK;
    };
    for (uint32_t axis = 0; axis < 3; ++axis) {
        out[axis] = std::bit_cast<uint32_t>(embedBelow(child.boundsMin[axis], bitsOf(axis)));
        out[3 + axis] =
            std::bit_cast<uint32_t>(embedAbove(child.boundsMax[axis], bitsOf(3 + axis)));
    }
}

// A record: both children's boxes with their words, in three texels.
void putRecord(const BvhNode& a, uint32_t wordA, const BvhNode& b, uint32_t wordB,
               glm::uvec4* out) {
    uint32_t words[12];
    putChild(a, wordA, words);
    putChild(b, wordB, words + 6);
    for (int t = 0; t < 3; ++t)
        out[t] = glm::uvec4(words[4 * t], words[4 * t + 1], words[4 * t + 2], words[4 * t + 3]);
}

}  // namespace

float embedBelow(float x, uint32_t bits) {
    return embed(x, bits & WORD_MASK, true);
}
float embedAbove(float x, uint32_t bits) {
    return embed(x, bits & WORD_MASK, false);
}

std::vector<glm::uvec4> packTraversalNodes(std::span<const BvhNode> nodes, uint32_t firstTexel) {
    std::vector<glm::uvec4> texels;
    if (nodes.empty() || (nodes[0].count == 0 && nodes[0].offset == 0)) {
        // The empty tree: boxes of NaN, which intersectBox never enters.
        const uint32_t nan = std::bit_cast<uint32_t>(std::nanf(""));
        texels.assign(VKP_BVH_RECORD_TEXELS, glm::uvec4(nan));
        return texels;
    }
    // Each interior node's record offset, in preorder (the root's is 0).
    std::vector<uint32_t> record(nodes.size(), 0);
    uint32_t next = firstTexel;
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].count != 0) continue;
        if (next > VKP_BVH_WORD_INDEX_MASK)
            throw std::length_error(
                "BVH: more node records than the 2^28 texels a node word indexes");
        record[i] = next;
        next += VKP_BVH_RECORD_TEXELS;
    }
    if (nodes[0].count != 0) {
        // A single leaf: a record whose two children are that leaf.
        const uint32_t word = childWord(nodes, 0, record);
        texels.resize(VKP_BVH_RECORD_TEXELS);
        putRecord(nodes[0], word, nodes[0], word, texels.data());
        return texels;
    }
    texels.resize(next - firstTexel);
    forEachChunk(nodes.size(), 0, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            if (nodes[i].count != 0) continue;
            const uint32_t a = static_cast<uint32_t>(i + 1), b = nodes[i].offset;
            putRecord(nodes[a], childWord(nodes, a, record), nodes[b], childWord(nodes, b, record),
                      &texels[record[i] - firstTexel]);
        }
    });
    return texels;
}

}  // namespace vkpath::bvh
