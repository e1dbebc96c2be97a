#include "bvh/wide_bvh.h"

#include <algorithm>

namespace vkpath::bvh {
namespace {

bool isLeaf(const shared::BvhNode& node) { return node.count > 0; }

float surfaceArea(const shared::BvhNode& node) {
    const glm::vec3 d = node.boundsMax - node.boundsMin;
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

// Appends the blocks of the leaf holding primitives [first, first + count);
// returns the index of the first.
uint32_t appendBlocks(std::span<const shared::BvhPrimitive> primitives, uint32_t first, uint32_t count, WideBvh& wide) {
    const auto start = uint32_t(wide.blocks.size());
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t lane = i % WideBvh::BLOCK;
        if (lane == 0) wide.blocks.emplace_back();
        WideBvh::Block& block = wide.blocks.back();
        const shared::BvhPrimitive& p = primitives[first + i];
        block.primitive[lane] = first + i;
        const float* coordinates[9] = {&p.p0.x, &p.p0.y, &p.p0.z, &p.p1.x, &p.p1.y,
                                       &p.p1.z, &p.p2.x, &p.p2.y, &p.p2.z};
        float* lanes[9] = {block.p0x, block.p0y, block.p0z, block.p1x, block.p1y,
                           block.p1z, block.p2x, block.p2y, block.p2z};
        for (int k = 0; k < 9; ++k) lanes[k][lane] = *coordinates[k];
        (p.kind == VKP_PRIMITIVE_SPHERE ? block.spheres : block.triangles) |= 1u << lane;
    }
    return start;
}

// Appends the wide node whose children are `binaryIndex`'s subtree opened up
// to WIDTH boxes; returns its index.
uint32_t collapseNode(std::span<const shared::BvhNode> binary, std::span<const shared::BvhPrimitive> primitives,
                      uint32_t binaryIndex, WideBvh& wide) {
    std::vector<uint32_t> slots;
    const shared::BvhNode& root = binary[binaryIndex];
    if (isLeaf(root))
        slots = {binaryIndex};
    else
        slots = {binaryIndex + 1, root.offset};
    while (slots.size() < WideBvh::WIDTH) {
        auto largest = slots.end();
        for (auto it = slots.begin(); it != slots.end(); ++it)
            if (!isLeaf(binary[*it]) &&
                (largest == slots.end() || surfaceArea(binary[*it]) > surfaceArea(binary[*largest])))
                largest = it;
        if (largest == slots.end()) break;
        const uint32_t opened = *largest;
        *largest = opened + 1;
        slots.push_back(binary[opened].offset);
    }

    const auto index = uint32_t(wide.nodes.size());
    wide.nodes.emplace_back();
    WideBvh::Node node{};
    node.children = uint32_t(slots.size());
    for (uint32_t i = 0; i < slots.size(); ++i) {
        const shared::BvhNode& child = binary[slots[i]];
        node.minX[i] = child.boundsMin.x;
        node.minY[i] = child.boundsMin.y;
        node.minZ[i] = child.boundsMin.z;
        node.maxX[i] = child.boundsMax.x;
        node.maxY[i] = child.boundsMax.y;
        node.maxZ[i] = child.boundsMax.z;
        if (isLeaf(child)) {
            node.child[i] = appendBlocks(primitives, child.offset, child.count, wide);
            node.count[i] = (child.count + WideBvh::BLOCK - 1) / WideBvh::BLOCK;
        } else {
            node.child[i] = collapseNode(binary, primitives, slots[i], wide);
            node.count[i] = 0;
        }
    }
    wide.nodes[index] = node;
    return index;
}

}  // namespace

WideBvh collapseBvh(std::span<const shared::BvhNode> binary, std::span<const shared::BvhPrimitive> primitives) {
    WideBvh wide;
    if (binary.empty() || (binary[0].count == 0 && binary[0].offset == 0)) return wide;  // empty tree
    wide.boundsMin = binary[0].boundsMin;
    wide.boundsMax = binary[0].boundsMax;
    collapseNode(binary, primitives, 0, wide);
    return wide;
}

}  // namespace vkpath::bvh
