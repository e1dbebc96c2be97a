// GLSL only: the BVH's two storage buffers, the accessors that
// shared/bvh_traverse.h reads them through, and the traversal itself. A kernel
// defines the binding indices first, then includes this once:
//
//   #define VKP_BVH_NODES_BINDING VKP_TRACE_BINDING_NODES
//   #define VKP_BVH_PRIMITIVES_BINDING VKP_TRACE_BINDING_PRIMITIVES
//   #include "shared/bvh_buffers.h"
//   ... Hit hit = bvhClosestHit(ray); bool blocked = bvhOccluded(shadowRay);
#ifndef VKPATH_SHARED_BVH_BUFFERS_H
#define VKPATH_SHARED_BVH_BUFFERS_H

#ifdef __cplusplus
#error "shared/bvh_buffers.h is GLSL only; C++ reads a BVH through host/bvh/bvh_view.h"
#endif

#include "shared/bvh.h"
#include "shared/intersect.h"
#include "shared/ray.h"

layout(binding = VKP_BVH_NODES_BINDING, scalar) readonly buffer BvhNodeBuffer {
    BvhNode bvhNodes[];
};
layout(binding = VKP_BVH_PRIMITIVES_BINDING, scalar) readonly buffer BvhPrimitiveBuffer {
    BvhPrimitive bvhPrimitives[];
};

BvhNode bvhNode(uint index) { return bvhNodes[index]; }
BvhPrimitive bvhPrimitive(uint index) { return bvhPrimitives[index]; }

#include "shared/bvh_traverse.h"

#endif  // VKPATH_SHARED_BVH_BUFFERS_H
