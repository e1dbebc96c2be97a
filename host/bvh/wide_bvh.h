// The CPU reference's tree: the binary BVH (bvh.h) collapsed into nodes of up
// to eight children, whose boxes are tested against a ray in one pass of
// eight-lane vector arithmetic (AVX on x86-64), where the binary traversal
// tests two boxes per node, one after the other. The GPU kernels keep the
// binary tree: on SIMD hardware each lane is a ray already.
//
//   bvh::WideBvh wide = bvh::collapseBvh(build.nodes);
//   shared::Hit hit = bvh::traceWide(view, wide, ray, false, alphaKey);
//
// The leaves are the binary tree's (ranges of the same leaf-ordered primitive
// array), tested with the same code (shared/bvh_leaf.h, through `view`), and a
// box is culled by the same test (shared/intersect.h intersectBox, lane by
// lane the same operations): so traceWide returns the binary traversal's hit
// bit for bit, ties included (shared/bvh_leaf.h).
//
// Collapsing follows Wald, Benthin and Boulos, "Getting Rid of Packets:
// Efficient SIMD Single-Ray Traversal using Multi-branching BVHs" (RT 2008):
// a wide node takes its binary node's two children, then repeatedly opens the
// interior child of largest surface area, until it has eight or only leaves.
// Traversal visits the hit children nearest first, with each one's entry
// distance on the stack so that a box entered beyond the current hit is
// skipped when popped.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#ifdef __AVX__
#include <immintrin.h>
#endif

#include "shared/bvh.h"
#include "shared/intersect.h"
#include "shared/ray.h"

namespace vkpath::bvh {

struct WideBvh {
    static constexpr uint32_t WIDTH = 8;
    // The deepest a wide node can be: collapsing never deepens the tree.
    static constexpr uint32_t MAX_DEPTH = VKP_BVH_MAX_DEPTH;

    // A node's children in structure-of-arrays form: one vector load per
    // bound and axis. Slots at or past `children` are unused (zero).
    struct alignas(32) Node {
        float minX[WIDTH], minY[WIDTH], minZ[WIDTH];
        float maxX[WIDTH], maxY[WIDTH], maxZ[WIDTH];
        uint32_t child[WIDTH];  // interior: index into nodes; leaf: its first primitive (leaf order)
        uint32_t count[WIDTH];  // leaf: its primitives (>= 1); interior: 0
        uint32_t children;      // slots in use, 1 to WIDTH
    };

    std::vector<Node> nodes;  // root at 0; empty for an empty tree
};

// The wide tree over `binary` (a BvhBuild's depth-first node array).
WideBvh collapseBvh(std::span<const shared::BvhNode> binary);

namespace wide_detail {

using Floats = float __attribute__((vector_size(32)));
using Ints = int32_t __attribute__((vector_size(32)));

inline Floats load(const float* values) {
    Floats v;
    std::memcpy(&v, values, sizeof v);
    return v;
}
// glm's min and max, lane by lane: the binary traversal's operations.
inline Floats minOf(Floats a, Floats b) { return b < a ? b : a; }
inline Floats maxOf(Floats a, Floats b) { return a < b ? b : a; }

// Bit i set where lane i of `mask` is true (all ones).
inline uint32_t laneBits(Ints mask) {
#ifdef __AVX__
    return uint32_t(_mm256_movemask_ps(__m256(mask)));
#else
    uint32_t bits = 0;
    for (uint32_t i = 0; i < WideBvh::WIDTH; ++i) bits |= uint32_t(mask[i] != 0) << i;
    return bits;
#endif
}

// shared/intersect.h intersectBox for the node's eight boxes: bit i of the
// result says whether the ray meets child i before or at tLimit; entries[i] is
// where it enters.
inline uint32_t intersectBoxes(const WideBvh::Node& node, const glm::vec3& origin, const glm::vec3& inverseDirection,
                               float tLimit, float entries[WideBvh::WIDTH]) {
    const Floats t0x = (load(node.minX) - origin.x) * inverseDirection.x;
    const Floats t0y = (load(node.minY) - origin.y) * inverseDirection.y;
    const Floats t0z = (load(node.minZ) - origin.z) * inverseDirection.z;
    const Floats t1x = (load(node.maxX) - origin.x) * inverseDirection.x;
    const Floats t1y = (load(node.maxY) - origin.y) * inverseDirection.y;
    const Floats t1z = (load(node.maxZ) - origin.z) * inverseDirection.z;
    const Floats zero = {};
    const Floats entry = maxOf(maxOf(minOf(t0x, t1x), minOf(t0y, t1y)), maxOf(minOf(t0z, t1z), zero));
    const Floats exit = minOf(minOf(maxOf(t0x, t1x), maxOf(t0y, t1y)), maxOf(t0z, t1z)) * VKP_BOX_SLACK;
    const Ints hit = (entry <= exit) & (entry <= tLimit * VKP_BOX_SLACK);
    std::memcpy(entries, &entry, sizeof entry);
    return laneBits(hit) & ((1u << node.children) - 1u);
}

}  // namespace wide_detail

// Closest hit (anyHit false) or any hit in [0, ray.tMax) of the tree `wide`
// collapsed from the BVH that `view` reads: the hit `view.bvhTrace` returns.
// `view` provides bvhTestPrimitive (shared/bvh_leaf.h included in it), which
// asks its alpha test with `alphaKey`.
template <typename View>
shared::Hit traceWide(const View& view, const WideBvh& wide, const shared::Ray& ray, bool anyHit,
                      uint32_t alphaKey) {
    shared::Hit hit{ray.tMax, VKP_NO_HIT, glm::vec2(0.0f)};
    if (wide.nodes.empty()) return hit;
    const shared::TriangleRay triangleRay = shared::makeTriangleRay(ray.origin, ray.direction);
    const glm::vec3 inverseDirection = shared::safeInverse(ray.direction);

    struct Entry {
        uint32_t child, count;  // as in WideBvh::Node; the root is (0, 0)
        float entry;            // where the ray enters its box
    };
    // Each interior node pops one entry and pushes at most WIDTH.
    Entry stack[(WideBvh::WIDTH - 1) * WideBvh::MAX_DEPTH + 1];
    uint32_t size = 0;
    stack[size++] = Entry{0, 0, 0.0f};
    while (size > 0) {
        const Entry top = stack[--size];
        if (!(top.entry <= hit.t * VKP_BOX_SLACK)) continue;  // the box lies beyond the hit found since
        if (top.count > 0) {
            for (uint32_t i = top.child; i < top.child + top.count; ++i)
                if (view.bvhTestPrimitive(ray, triangleRay, i, alphaKey, hit) && anyHit) return hit;
            continue;
        }
        const WideBvh::Node& node = wide.nodes[top.child];
        float entries[WideBvh::WIDTH];
        uint32_t bits = wide_detail::intersectBoxes(node, ray.origin, inverseDirection, hit.t, entries);
        // Push the hit children farthest first, so the nearest is popped next.
        const uint32_t first = size;
        for (; bits != 0; bits &= bits - 1) {
            const uint32_t slot = uint32_t(__builtin_ctz(bits));
            Entry e{node.child[slot], node.count[slot], entries[slot]};
            uint32_t j = size++;
            for (; j > first && stack[j - 1].entry < e.entry; --j) stack[j] = stack[j - 1];
            stack[j] = e;
        }
    }
    return hit;
}

}  // namespace vkpath::bvh
