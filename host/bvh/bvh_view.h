// CPU traversal of a flattened BVH with the kernels' own code: the bodies of
// shaders/shared/bvh_leaf.h and bvh_traverse.h become the const member
// functions of BvhView, reading the two arrays through std::span where a
// kernel reads its texel buffers. The tests and benchmarks trace with it, as
// the yardstick of the GPU's traversal and of the CPU reference's wide tree
// (host/bvh/wide_bvh.h, which tests leaves through it):
//
//   shared::BvhView view{build.nodes, build.primitives};
//   shared::Hit hit = view.bvhClosestHit(ray);
//   bool blocked = view.bvhOccluded(shadowRay);
//
// It lives in vkpath::shared because the included code names shared types and
// GLM functions unqualified, as GLSL does.
#pragma once

#include <span>

#include "shared/bvh.h"
#include "shared/intersect.h"
#include "shared/ray.h"

namespace vkpath::shared {

struct BvhView {
    std::span<const uvec4> nodes;              // as bvh::BvhBuild::traversalNodes
    std::span<const BvhPrimitive> primitives;  // leaf order, as bvh::BvhBuild::primitives

    // The accessors shared/bvh_leaf.h and bvh_traverse.h read through, and its alpha test:
    // a BVH alone has no materials, so every candidate hit stands
    // (reference/path_tracer_view.h tests alpha).
    uvec4 bvhNodeTexel(uint texel) const { return nodes[texel]; }
    BvhPrimitive bvhPrimitive(uint index) const { return primitives[index]; }
    bool bvhAlphaTest(BvhPrimitive, vec2, uint) const { return true; }

#include "shared/bvh_leaf.h"
#include "shared/bvh_traverse.h"
};

}  // namespace vkpath::shared
