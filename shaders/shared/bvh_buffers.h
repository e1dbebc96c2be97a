// GLSL only: the BVH's two arrays, the accessors that shared/bvh_traverse.h
// reads them through, and the traversal itself. The arrays reach a kernel in
// one of two ways, fixed when its pipeline is built (specialisation constant
// VKP_SPEC_SCENE_BY_ADDRESS):
//
//   bound (false, the default): two uniform texel buffer bindings (below).
//     Scenes are bound while each array fits one binding
//     (vk::bufferLimits: 16 x maxTexelBufferElements bytes; 2 GiB on
//     lavapipe, about 44 million primitives), the limit every other scene
//     array is bound under;
//   by address (true): buffer references (GL_EXT_buffer_reference) to the
//     same arrays, limited only by the size of one buffer. Slower than
//     storage-buffer bindings on lavapipe, which are slower again than the
//     texel buffers (docs/BENCHMARKS.md, "Scene data on lavapipe: texel
//     buffers, storage buffers, device addresses"), so only scenes too large
//     for a binding use it (host/bvh/gpu_bvh.h decides).
//
// The pipeline compiler folds the constant, so each pipeline keeps only one
// path; both bindings are declared either way (a placeholder is bound to them
// in the address path). A kernel enables GL_EXT_buffer_reference,
// GL_EXT_buffer_reference_uvec2 and GL_EXT_samplerless_texture_functions,
// defines the binding indices and where the addresses are (a BvhAddresses
// expression), then includes this once:
//
//   #define VKP_BVH_NODES_BINDING VKP_TRACE_BINDING_NODES
//   #define VKP_BVH_PRIMITIVES_BINDING VKP_TRACE_BINDING_PRIMITIVES
//   #define VKP_BVH_ADDRESSES push.bvh
//   #include "shared/bvh_buffers.h"
//   ... Hit hit = bvhClosestHit(ray); bool blocked = bvhOccluded(shadowRay);
#ifndef VKPATH_SHARED_BVH_BUFFERS_H
#define VKPATH_SHARED_BVH_BUFFERS_H

#ifdef __cplusplus
#error "shared/bvh_buffers.h is GLSL only; C++ reads a BVH through host/bvh/bvh_view.h"
#endif

#include "shared/bindings.h"
#include "shared/bvh.h"
#include "shared/intersect.h"
#include "shared/ray.h"

layout(constant_id = VKP_SPEC_SCENE_BY_ADDRESS) const bool sceneByAddress = false;

// Bound, the arrays are read as uniform texel buffers of 16-byte texels
// (R32G32B32A32_UINT): a node record is three texels, a primitive three. lavapipe
// reads a storage buffer at an index that differs between SIMD lanes one
// lane and one 4-byte component at a time, each behind its own bounds test
// and branch (12 of them per lane for a primitive); a texel fetch is one
// call per texel for the whole SIMD group, into a sampling function lavapipe
// compiles for the binding (GALLIVM_DEBUG=asm shows both). The traversal runs
// faster so (docs/BENCHMARKS.md, "Scene data on lavapipe"), and GPUs fetch
// texels as fast as they load. Each fetch still costs a call and the spilling of live registers
// around it, so the traversal reads each node once (shared/bvh_traverse.h).
layout(binding = VKP_BVH_NODES_BINDING) uniform utextureBuffer bvhNodeTexels;
layout(binding = VKP_BVH_PRIMITIVES_BINDING) uniform utextureBuffer bvhPrimitiveTexels;

// 16: the arrays start at a buffer's start, and every node and primitive at a
// multiple of 16 bytes within it (32- and 48-byte elements).
layout(buffer_reference, scalar, buffer_reference_align = 16) readonly buffer BvhNodeTexelArray {
    uvec4 v[];
};
layout(buffer_reference, scalar, buffer_reference_align = 16) readonly buffer BvhPrimitiveArray {
    BvhPrimitive v[];
};

uvec4 bvhNodeTexel(uint texel) {
    if (sceneByAddress) return BvhNodeTexelArray(VKP_BVH_ADDRESSES.nodes).v[texel];
    return texelFetch(bvhNodeTexels, int(texel));
}
BvhPrimitive bvhPrimitive(uint index) {
    if (sceneByAddress) return BvhPrimitiveArray(VKP_BVH_ADDRESSES.primitives).v[index];
    uvec4 t[3] = uvec4[3](texelFetch(bvhPrimitiveTexels, int(3u * index)),
                          texelFetch(bvhPrimitiveTexels, int(3u * index + 1u)),
                          texelFetch(bvhPrimitiveTexels, int(3u * index + 2u)));
    BvhPrimitive r;
    VKP_RECORD_DECODE(VKP_BVH_PRIMITIVE_FIELDS)
    return r;
}

#include "shared/bvh_leaf.h"
// The kernels' `_rayquery` variants trace by the device's acceleration
// structures, the others by their own traversal of the tree.
#ifdef VKP_RAY_QUERY
#include "shared/bvh_ray_query.h"
#else
#include "shared/bvh_traverse.h"
#endif

#endif  // VKPATH_SHARED_BVH_BUFFERS_H
