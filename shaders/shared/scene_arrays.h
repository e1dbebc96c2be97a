// The table of the scene's arrays (besides the BVH's two, shared/bvh_buffers.h,
// and the SceneInfo): the one list of them, read by GLSL and C++. From it
// come the kernels' texel-buffer bindings (stages/lib/scene_access.glsl), the
// SceneAddresses record (shared/scene_addresses.h), the device buffers, their
// upload, size and bindings (host/wavefront/gpu_scene, renderer.cpp) and the
// CPU reference's view of them (host/reference/path_tracer_view.h). What a
// record holds and how its texels decode stay beside its struct and its
// accessor in scene_access.glsl.
//
// One row per array:
//
//   X(BINDING, name, Record, ACCESS, member)
//
//   BINDING  its binding index in the stage kernels (shared/wavefront.h)
//   name     the GpuScene buffer, the kernels' `nameTexels` texel buffer and,
//            for SPANS arrays, the SceneAddresses field
//   Record   the C++ element type of the host's array
//   ACCESS   BOUND: always read through its binding (one record per material
//            or texture: it does not grow with the geometry); SPANS: read by
//            address instead when the scene's arrays outgrow a binding
//            (VKP_SPEC_SCENE_BY_ADDRESS, shared/bindings.h)
//   member   the array in wavefront::SceneTables (host/wavefront/gpu_scene.h)
//
// Every array's buffer is whole 16-byte texels (a record of 16 bytes or a
// multiple of it is a texel or more; smaller ones are several to a texel),
// at least one: an array the scene does not use is one texel, since Vulkan
// needs every declared binding bound.
//
// Adding an array: a binding number in shared/wavefront.h, a row here, the
// host vector in SceneTables, its accessor in stages/lib/scene_access.glsl
// and in SceneTablesView (path_tracer_view.h), its checks in
// SceneTablesView's constructor.
#ifndef VKPATH_SHARED_SCENE_ARRAYS_H
#define VKPATH_SHARED_SCENE_ARRAYS_H

#include "shared/wavefront.h"

#define VKP_SCENE_ARRAYS(X)                                                                \
    X(VKP_WF_MATERIALS, materials, Material, BOUND, materials)                             \
    X(VKP_WF_LIGHTS, lights, Light, SPANS, lights)                                         \
    X(VKP_WF_LIGHT_ALIAS, lightAlias, AliasEntry, SPANS, lightAlias)                       \
    X(VKP_WF_PRIMITIVE_LIGHT, primitiveLight, uint32_t, SPANS, primitiveLight)             \
    X(VKP_WF_ENV_ALIAS, envAlias, AliasEntry, SPANS, envAlias)                             \
    X(VKP_WF_ENV_RADIANCE, envRadiance, glm::vec4, SPANS, envRadiance)                     \
    X(VKP_WF_TRIANGLE_VERTICES, triangleVertices, TriangleVertices, SPANS,                 \
      surface.triangleVertices)                                                            \
    X(VKP_WF_VERTEX_NORMALS, vertexNormals, glm::vec4, SPANS, surface.vertexNormals)       \
    X(VKP_WF_VERTEX_TEXCOORDS, vertexTexcoords, glm::vec4, SPANS, surface.vertexTexcoords) \
    X(VKP_WF_VERTEX_COLORS, vertexColors, glm::vec4, SPANS, surface.vertexColors)          \
    X(VKP_WF_TEXELS, texels, glm::uvec2, SPANS, textures.texels)                           \
    X(VKP_WF_VERTEX_TANGENTS, vertexTangents, glm::vec4, SPANS, surface.vertexTangents)    \
    X(VKP_WF_TEXTURES, textures, TextureInfo, BOUND, textures.textures)                    \
    X(VKP_WF_TEXTURE_SLOTS, textureSlots, TextureSlot, BOUND, textures.slots)              \
    X(VKP_WF_MATERIAL_ALPHA, materialAlpha, MaterialAlpha, BOUND, materialAlpha)           \
    X(VKP_WF_MICROFACET_ALBEDO, microfacetAlbedo, float, BOUND, microfacetAlbedo)          \
    X(VKP_WF_LIGHT_TREE, lightTree, LightTreeNode, SPANS, lightTree.nodes)                 \
    X(VKP_WF_LIGHT_TREE_TRAIL, lightTreeTrail, uint32_t, SPANS, lightTree.trails)          \
    X(VKP_WF_MEDIA, media, Medium, BOUND, media)                                           \
    X(VKP_WF_GRID_MEDIUM, gridMedium, GridMedium, BOUND, gridMedium)                       \
    X(VKP_WF_GRID_DENSITY, gridDensity, float, SPANS, gridDensity)                         \
    X(VKP_WF_GRID_MAJORANT, gridMajorant, float, SPANS, gridMajorant)

// `VKP_SCENE_ARRAY_IF_SPANS_##access(x)` keeps x (without commas: GLSL's
// preprocessor has no variadic macros) for SPANS rows and drops it for BOUND
// ones: for what only address-read arrays have.
#define VKP_SCENE_ARRAY_IF_SPANS_SPANS(x) x
#define VKP_SCENE_ARRAY_IF_SPANS_BOUND(x)
// 1 for SPANS rows, 0 for BOUND ones.
#define VKP_SCENE_ARRAY_SPANS_SPANS 1
#define VKP_SCENE_ARRAY_SPANS_BOUND 0

#endif  // VKPATH_SHARED_SCENE_ARRAYS_H
