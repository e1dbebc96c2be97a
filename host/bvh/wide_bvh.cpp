#include "bvh/wide_bvh.h"

#include <algorithm>
#include <stdexcept>

#include "bvh/bvh.h"

namespace vkpath::bvh {
namespace {

bool isLeaf(const shared::BvhNode& node) {
    return node.count > 0;
}

float surfaceArea(const shared::BvhNode& node) {
    const glm::vec3 d = node.boundsMax - node.boundsMin;
    return d.x * d.y + d.y * d.z + d.z * d.x;
}

// Appends the blocks of the leaf holding primitives [first, first + count),
// its triangles, then its spheres, then its instances, each kind in blocks of
// its own in leaf order; returns the index of the first block.
uint32_t appendBlocks(std::span<const shared::BvhPrimitive> primitives, uint32_t first,
                      uint32_t count, WideBvh& wide) {
    const auto start = uint32_t(wide.blocks.size());
    for (const uint32_t kind :
         {VKP_PRIMITIVE_TRIANGLE, VKP_PRIMITIVE_SPHERE, VKP_PRIMITIVE_INSTANCE}) {
        uint32_t lane = WideBvh::BLOCK;
        for (uint32_t i = first; i < first + count; ++i) {
            const shared::BvhPrimitive& p = primitives[i];
            if (p.kind != kind) continue;
            if (lane == WideBvh::BLOCK) {
                wide.blocks.emplace_back();
                lane = 0;
            }
            WideBvh::Block& block = wide.blocks.back();
            block.primitive[lane] = i;
            const float* coordinates[9] = {&p.p0.x, &p.p0.y, &p.p0.z, &p.p1.x, &p.p1.y,
                                           &p.p1.z, &p.p2.x, &p.p2.y, &p.p2.z};
            float* lanes[9] = {block.p0x, block.p0y, block.p0z, block.p1x, block.p1y,
                               block.p1z, block.p2x, block.p2y, block.p2z};
            for (int k = 0; k < 9; ++k) lanes[k][lane] = *coordinates[k];
            (kind == VKP_PRIMITIVE_TRIANGLE ? block.triangles
             : kind == VKP_PRIMITIVE_SPHERE ? block.spheres
                                            : block.instances) |= 1u << lane;
            ++lane;
        }
    }
    return start;
}

// How many blocks appendBlocks makes of primitives [first, first + count),
// and how many of the primitives are instances.
struct BlockCount {
    uint32_t blocks = 0;
    uint32_t instances = 0;
};
BlockCount blockCount(std::span<const shared::BvhPrimitive> primitives, uint32_t first,
                      uint32_t count) {
    uint32_t spheres = 0, instances = 0;
    for (uint32_t i = first; i < first + count; ++i) {
        spheres += primitives[i].kind == VKP_PRIMITIVE_SPHERE;
        instances += primitives[i].kind == VKP_PRIMITIVE_INSTANCE;
    }
    auto blocks = [](uint32_t n) { return (n + WideBvh::BLOCK - 1) / WideBvh::BLOCK; };
    return {blocks(count - spheres - instances) + blocks(spheres) + blocks(instances), instances};
}

// What testing an instance costs in block tests (a bottom-level traversal):
// enough that leaves of instances are not merged, whose boxes the binary
// traversal would cull.
constexpr float INSTANCE_COST = 16.0f;

// What collapsing knows of each binary node's subtree: its primitives,
// [first, first + count) in leaf order (a depth-first tree's subtree holds a
// contiguous range), and whether it becomes one wide leaf.
struct Subtree {
    uint32_t first = 0, count = 0;
    bool leaf = false;
    float cost = 0.0f;  // expected tests of a ray that meets its box, in block tests
};

// What descending into a binary node costs beyond testing its children, in
// block tests: nothing, as its two boxes take slots of the wide node's one
// vector pass. (At 0.5 the walls of a Cornell box merge into leaves whose
// boxes span the room, and rays from inside it, every ray of a path tracer,
// meet them all: docs/BENCHMARKS.md, "Tried, not kept".)
constexpr float SPLIT_COST = 0.0f;

// Fills subtrees[index] and those below it. A subtree of at most
// LEAF_PRIMITIVES primitives becomes one wide leaf when testing it whole is
// expected to cost no more than descending into it (the surface area
// heuristic: a child is met by a ray that meets its parent with the ratio of
// their box areas); a binary leaf is a wide leaf whatever its size.
Subtree measureSubtree(std::span<const shared::BvhNode> binary,
                       std::span<const shared::BvhPrimitive> primitives, uint32_t index,
                       std::vector<Subtree>& subtrees) {
    const shared::BvhNode& node = binary[index];
    auto leafCost = [&](uint32_t first, uint32_t count) {
        const BlockCount c = blockCount(primitives, first, count);
        return float(c.blocks) + INSTANCE_COST * float(c.instances);
    };
    if (isLeaf(node))
        return subtrees[index] =
                   Subtree{node.offset, node.count, true, leafCost(node.offset, node.count)};
    const Subtree left = measureSubtree(binary, primitives, index + 1, subtrees);
    const Subtree right = measureSubtree(binary, primitives, node.offset, subtrees);
    if (left.first + left.count != right.first)
        throw std::logic_error("BVH subtree primitives are not contiguous");
    const float area = std::max(surfaceArea(node), 1e-30f);
    const float splitCost = SPLIT_COST + (surfaceArea(binary[index + 1]) * left.cost +
                                          surfaceArea(binary[node.offset]) * right.cost) /
                                             area;
    Subtree subtree{left.first, left.count + right.count, false, splitCost};
    if (subtree.count <= WideBvh::LEAF_PRIMITIVES) {
        const float cost = leafCost(subtree.first, subtree.count);
        if (cost <= splitCost) {
            subtree.leaf = true;
            subtree.cost = cost;
        }
    }
    return subtrees[index] = subtree;
}

struct Collapse {
    std::span<const shared::BvhNode> binary;
    std::span<const shared::BvhPrimitive> primitives;
    std::vector<Subtree> subtrees;
    WideBvh& wide;

    bool leaf(uint32_t index) const { return subtrees[index].leaf; }

    // Appends the wide node whose children are `binaryIndex`'s subtree opened
    // up to WIDTH boxes; returns its index.
    uint32_t node(uint32_t binaryIndex) {
        std::vector<uint32_t> slots;
        if (leaf(binaryIndex))
            slots = {binaryIndex};
        else
            slots = {binaryIndex + 1, binary[binaryIndex].offset};
        while (slots.size() < WideBvh::WIDTH) {
            auto largest = slots.end();
            for (auto it = slots.begin(); it != slots.end(); ++it)
                if (!leaf(*it) && (largest == slots.end() ||
                                   surfaceArea(binary[*it]) > surfaceArea(binary[*largest])))
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
            if (leaf(slots[i])) {
                const Subtree range = subtrees[slots[i]];
                node.child[i] = appendBlocks(primitives, range.first, range.count, wide);
                node.count[i] = blockCount(primitives, range.first, range.count).blocks;
            } else {
                node.child[i] = this->node(slots[i]);
                node.count[i] = 0;
            }
        }
        wide.nodes[index] = node;
        return index;
    }
};

}  // namespace

WideBvh collapseBvh(std::span<const shared::BvhNode> binary,
                    std::span<const shared::BvhPrimitive> primitives,
                    std::span<const uint32_t> objectRoots) {
    WideBvh wide;
    if (binary.empty() || (binary[0].count == 0 && binary[0].offset == 0))
        return wide;  // empty tree
    Collapse collapse{binary, primitives, std::vector<Subtree>(binary.size()), wide};
    measureSubtree(binary, primitives, 0, collapse.subtrees);
    collapse.node(0);
    for (const uint32_t root : objectRoots) {
        measureSubtree(binary, primitives, root, collapse.subtrees);
        wide.objectRoots.push_back(collapse.node(root));
    }
    return wide;
}

WideBvh collapseBvh(const BvhBuild& build) {
    const std::vector<uint32_t> roots = build.objectRootNodes();
    return collapseBvh(build.nodes, build.primitives, roots);
}

}  // namespace vkpath::bvh
