// The BVH as the stage kernels read it: bound (VKP_WF_BVH_NODES,
// VKP_WF_BVH_PRIMITIVES) or by the addresses in the SceneAddresses buffer,
// as the pipeline's VKP_SPEC_SCENE_BY_ADDRESS says (shared/bvh_buffers.h).
// The traversal's alpha test is shared/path_tracer.h's, defined after it
// (stages/lib/scene_access.glsl includes both).
#include "shared/bvh.h"
#include "shared/scene_addresses.h"

bool bvhAlphaTest(BvhPrimitive triangle, vec2 barycentrics, uint alphaKey);

layout(binding = VKP_WF_SCENE_ADDRESSES, scalar) readonly buffer SceneAddressBuffer {
    SceneAddresses sceneAddresses;
};

#define VKP_BVH_NODES_BINDING VKP_WF_BVH_NODES
#define VKP_BVH_PRIMITIVES_BINDING VKP_WF_BVH_PRIMITIVES
#define VKP_BVH_ADDRESSES sceneAddresses.bvh
#include "shared/bvh_buffers.h"
