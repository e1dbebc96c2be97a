// Where the scene's arrays lie in device memory, for stage kernels built to
// read them by address (VKP_SPEC_SCENE_BY_ADDRESS, shared/bindings.h): scenes
// with an array larger than one binding may span. Each is a
// VkDeviceAddress as (low, high) words (GL_EXT_buffer_reference_uvec2); all
// zero when the arrays are bound instead (host/wavefront/gpu_scene.h).
#ifndef VKPATH_SHARED_SCENE_ADDRESSES_H
#define VKPATH_SHARED_SCENE_ADDRESSES_H

#include "shared/bvh.h"
#include "shared/compat.h"
#include "shared/scene_arrays.h"

VKP_NAMESPACE_BEGIN

// The arrays whose length grows with the scene: the BVH's, then the SPANS
// rows of shared/scene_arrays.h in its order (per primitive, per emitter, per
// environment texel, per triangle, per vertex, per texture texel). The BOUND
// ones (materials, textures) and the SceneInfo stay bound.
#define VKP_ADDRESS_FIELD(index, name, Record, access, member) \
    VKP_SCENE_ARRAY_IF_SPANS_##access(uvec2 name;)
struct SceneAddresses {
    BvhAddresses bvh;
    VKP_SCENE_ARRAYS(VKP_ADDRESS_FIELD)
};
#undef VKP_ADDRESS_FIELD

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::SceneAddresses) == 160);
#endif

#endif  // VKPATH_SHARED_SCENE_ADDRESSES_H
