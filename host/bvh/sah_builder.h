// The binned SAH builder's tree over primitive boxes (Wald, "On fast
// Construction of SAH-based Bounding Volume Hierarchies", IEEE Symposium on
// Interactive Ray Tracing 2007), for bvh.cpp's buildBvh, which collects the
// boxes and flattens the tree.
//
//   std::vector<BuildPrimitive> boxes;   // BuildPrimitive(bounds, origin) each
//   std::vector<BuildNode> nodes = buildTree(options, boxes);  // boxes now in leaf order
#pragma once

#include <bit>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "bvh/bvh.h"

namespace vkpath::bvh {

constexpr float BUILD_INF = std::numeric_limits<float>::infinity();

struct Aabb {
    glm::vec3 lo{BUILD_INF};
    glm::vec3 hi{-BUILD_INF};

    void grow(const Aabb& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    // Half the surface area (the SAH only uses ratios).
    float halfArea() const {
        if (empty()) return 0.0f;
        const glm::vec3 e = hi - lo;
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
};

// Four floats in one SIMD register (GCC's and Clang's vector extension): the
// builder's boxes, bins and bounds, so that growing a box is one min and one
// max, not three of each.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));

// One primitive as the builder moves it: its box's corners, each in the
// first three lanes of a register, and the index of its origin (what the
// caller needs to flatten it) in the lower corner's fourth lane, as bits.
// 32 bytes, since every level of the build reads and moves them all. Its
// centroid is its box's centre.
struct alignas(16) BuildPrimitive {
    Float4 lo;
    Float4 hi;  // fourth lane 0

    BuildPrimitive() = default;
    BuildPrimitive(const Aabb& bounds, uint32_t origin)
        : lo{bounds.lo.x, bounds.lo.y, bounds.lo.z, std::bit_cast<float>(origin)},
          hi{bounds.hi.x, bounds.hi.y, bounds.hi.z, 0.0f} {}

    uint32_t origin() const { return std::bit_cast<uint32_t>(lo[3]); }
    Aabb bounds() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
    // In the first three lanes; the fourth is 0 (the origin's bits are
    // masked off before any arithmetic: as a float they may be subnormal).
    Float4 centroid() const {
        const Int4 xyz{-1, -1, -1, 0};
        const Float4 loXyz = std::bit_cast<Float4>(std::bit_cast<Int4>(lo) & xyz);
        return (loXyz + hi) * 0.5f;
    }
};
static_assert(sizeof(BuildPrimitive) == 32);

// A node before flattening: interior nodes keep their second child's index
// in `offset`, relative to the start of the vector they were built into.
struct BuildNode {
    Aabb bounds;
    uint32_t offset = 0;
    uint32_t count = 0;  // 0: interior
};

// The tree over `primitives`, reordering them into leaf order: its nodes in
// depth-first order, interior offsets relative to the vector, leaf ranges to
// `primitives`. Empty for no primitives. The same tree for any
// options.threads. Throws std::invalid_argument when the primitives cannot fit
// below options.maxDepth.
std::vector<BuildNode> buildTree(const BvhOptions& options,
                                 std::vector<BuildPrimitive>& primitives);

}  // namespace vkpath::bvh
