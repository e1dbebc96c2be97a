// The node array the traversal reads (shaders/shared/bvh.h has the layout):
// each interior node of a BvhBuild's tree as one record of three 16-byte
// texels holding its children's boxes, with each child's word (leaf or
// interior, where) in the low mantissa bits of its box's floats.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "shared/bvh.h"

namespace vkpath::bvh {

// The records of `nodes` (a BvhBuild's depth-first tree, interior offsets
// relative to the span), the root's first, for an array in which they start
// at texel `firstTexel` (a bottom-level tree after the scene's: the child
// words of interior nodes count from the array's start).
// Throws std::length_error for a leaf of more than VKP_BVH_MAX_LEAF_COUNT
// primitives, a primitive index or record offset of 2^28 or more, or a bound
// whose magnitude is too close to FLT_MAX to move outward.
std::vector<glm::uvec4> packTraversalNodes(std::span<const shared::BvhNode> nodes,
                                           uint32_t firstTexel = 0);

// The float nearest `x` at or below it (at or above it: embedAbove) whose low
// VKP_BVH_WORD_BITS bits are `bits`: at most 2^(VKP_BVH_WORD_BITS + 1) - 1
// ulps away. A magnitude below 2^-100 (zero included) is first moved to
// -2^-100 (below) or 2^-100 (above), so the result is a normal float.
float embedBelow(float x, uint32_t bits);
float embedAbove(float x, uint32_t bits);

}  // namespace vkpath::bvh
