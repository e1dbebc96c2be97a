// Test kernel: any-hit (shadow) BVH traversal of a buffer of rays, one flag
// per ray: 1 if anything lies in [0, tMax), else 0.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#extension GL_EXT_samplerless_texture_functions : require
#include "stages/lib/float_controls.glsl"  // as in the intersect stage

#include "shared/bindings.h"
#include "shared/bvh.h"
#include "shared/ray.h"

layout(push_constant, scalar) uniform Push {
    TracePush push;
};
// Opaque geometry: every candidate hit stands (shared/bvh_traverse.h).
bool bvhAlphaTest(BvhPrimitive triangle, vec2 barycentrics, uint alphaKey) { return true; }
#define VKP_BVH_ADDRESSES push.bvh
#define VKP_BVH_NODES_BINDING VKP_TRACE_BINDING_NODES
#define VKP_BVH_PRIMITIVES_BINDING VKP_TRACE_BINDING_PRIMITIVES
#include "shared/bvh_buffers.h"

layout(local_size_x_id = VKP_SPEC_WORKGROUP_SIZE) in;

layout(binding = VKP_TRACE_BINDING_RAYS, scalar) readonly buffer RayBuffer {
    Ray rays[];
};
layout(binding = VKP_TRACE_BINDING_RESULTS, scalar) writeonly buffer OcclusionBuffer {
    uint occluded[];
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    occluded[i] = bvhOccluded(rays[i]) ? 1u : 0u;
}
