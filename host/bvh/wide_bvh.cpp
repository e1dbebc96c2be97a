#include "bvh/wide_bvh.h"

#include <algorithm>

namespace vkpath::bvh {
namespace {

bool isLeaf(const shared::BvhNode& node) { return node.count > 0; }

float surfaceArea(const shared::BvhNode& node) {
    const glm::vec3 d = node.boundsMax - node.boundsMin;
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

// Appends the wide node whose children are `binaryIndex`'s subtree opened up
// to WIDTH boxes; returns its index.
uint32_t collapseNode(std::span<const shared::BvhNode> binary, uint32_t binaryIndex, WideBvh& wide) {
    std::vector<uint32_t> slots;
    const shared::BvhNode& root = binary[binaryIndex];
    if (isLeaf(root))
        slots = {binaryIndex};
    else
        slots = {binaryIndex + 1, root.offset};
    while (slots.size() < WideBvh::WIDTH) {
        auto largest = slots.end();
        for (auto it = slots.begin(); it != slots.end(); ++it)
            if (!isLeaf(binary[*it]) && (largest == slots.end() || surfaceArea(binary[*it]) > surfaceArea(binary[*largest])))
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
        node.count[i] = child.count;
        node.child[i] = isLeaf(child) ? child.offset : collapseNode(binary, slots[i], wide);
    }
    wide.nodes[index] = node;
    return index;
}

}  // namespace

WideBvh collapseBvh(std::span<const shared::BvhNode> binary) {
    WideBvh wide;
    if (binary.empty() || (binary[0].count == 0 && binary[0].offset == 0)) return wide;  // empty tree
    collapseNode(binary, 0, wide);
    return wide;
}

}  // namespace vkpath::bvh
