// Where the scene's arrays lie in device memory, for stage kernels built to
// read them by address (VKP_SPEC_SCENE_BY_ADDRESS, shared/bindings.h): scenes
// with an array larger than one binding may span. Each is a
// VkDeviceAddress as (low, high) words (GL_EXT_buffer_reference_uvec2); all
// zero when the arrays are bound instead (host/wavefront/gpu_scene.h).
#ifndef VKPATH_SHARED_SCENE_ADDRESSES_H
#define VKPATH_SHARED_SCENE_ADDRESSES_H

#include "shared/bvh.h"
#include "shared/compat.h"

VKP_NAMESPACE_BEGIN

// The arrays whose length grows with the scene: per node, per primitive, per
// emitter, per environment texel, per triangle and per vertex. (Materials and
// the SceneInfo stay bound.)
struct SceneAddresses {
    BvhAddresses bvh;
    uvec2 lights;          // Light[]
    uvec2 lightAlias;      // AliasEntry[lightCount]
    uvec2 primitiveLight;  // uint[primitives]
    uvec2 envAlias;        // AliasEntry[texels]
    uvec2 envRadiance;     // vec4[texels], w unused
    uvec2 triangleVertices;  // TriangleVertices[triangles]
    uvec2 vertexNormals;     // vec4[vertices], w unused
    uvec2 vertexTexcoords;   // vec4[vertices]: TEXCOORD_0, TEXCOORD_1
    uvec2 vertexColors;      // vec4[vertices]
    uvec2 texels;            // uvec2[texels]: the texture store (shared/texture.h)
    uvec2 vertexTangents;    // vec4[vertices]
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::SceneAddresses) == 104);
#endif

#endif  // VKPATH_SHARED_SCENE_ADDRESSES_H
