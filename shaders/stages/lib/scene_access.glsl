// The scene's buffers and the accessors shared/path_tracer.h reads them
// through, then the path tracer itself: its per-vertex math and its loop
// (shared/integrator.h).
#include "shared/alpha.h"
#include "shared/bsdf.h"
#include "shared/path_state.h"
#include "shared/light_tree.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/medium.h"
#include "shared/mesh_attributes.h"
#include "shared/phase.h"
#include "shared/rng.h"
#include "shared/scene_arrays.h"
#include "shared/scene_data.h"
#include "shared/texture.h"

#include "stages/lib/scene_bvh.glsl"

// The guide spheres (centre, radius) follow the SceneInfo (SceneInfo::guideSphereCount).
layout(binding = VKP_WF_SCENE_INFO, scalar) readonly buffer SceneInfoBuffer {
    SceneInfo sceneInfoData;
    vec4 guideSpheres[];
};
// The arrays read at every bounce or texture lookup come as texel buffers of
// 16-byte texels, as the BVH does (shared/bvh_buffers.h says why), one per
// row of shared/scene_arrays.h, named after it (materialsTexels, ...):
// records of 16 bytes or a multiple of it (materials, lights, alias entries,
// triangle vertices, vertex attributes, the environment's radiance, texture
// records, slots and alpha records; the vec3 arrays are stored as vec4 and
// the alias entries and texture slots padded for it) a texel or more each,
// smaller ones (the primitive-to-light map: four per texel; the half-float
// texture store: two RGBA texels per texel) several to a texel. Only the
// SceneInfo is a storage buffer: every invocation reads the same bytes.
#define VKP_TEXEL_BUFFER(index, name, Record, access, member) \
    layout(binding = index) uniform utextureBuffer name##Texels;
VKP_SCENE_ARRAYS(VKP_TEXEL_BUFFER)
#undef VKP_TEXEL_BUFFER

// The same arrays by address (sceneByAddress: scenes beyond a binding).
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer LightArray { Light v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer AliasArray { AliasEntry v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer LightTreeNodeArray {
    LightTreeNode v[];
};
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer UintArray { uint v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer FloatArray { float v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Vec4Array { vec4 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Uvec2Array { uvec2 v[]; };
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer TriangleVerticesArray {
    TriangleVertices v[];
};

SceneInfo sceneInfo() { return sceneInfoData; }
vec4 sceneGuideSphere(uint i) { return guideSpheres[i]; }
// A material's texels are read only where a feature of the kernel reads
// their fields (the others stay zero, which no code of the kernel reads): on
// lavapipe each texel fetch is a call into a sampling function, and a
// glass-and-diffuse box reads three of the five. Every record's fields are
// decoded from its texels by its field list (shared/records.h).
Material sceneMaterial(uint i) {
    int first = int(11u * i);
    uvec4 t[11];
    t[0] = texelFetch(materialsTexels, first);  // reflectance, kind
    t[1] = hasFeature(VKP_FEATURES_TRANSMITS | VKP_FEATURES_MICROFACET | VKP_FEATURE_REGULARIZE)
               ? texelFetch(materialsTexels, first + 1) : uvec4(0u);  // transmittance (k, F0), ior
    t[2] = hasFeature(VKP_FEATURE_EMISSIVE_SURFACES | VKP_FEATURE_TEXTURES | VKP_FEATURE_NORMAL_MAPS)
               ? texelFetch(materialsTexels, first + 2) : uvec4(0u);  // emission, textures
    t[3] = hasFeature(VKP_FEATURES_MICROFACET | VKP_FEATURE_REGULARIZE | VKP_FEATURE_THIN_WALLED)
               ? texelFetch(materialsTexels, first + 3) : uvec4(0u);  // roughness, metallic, specular, flags
    t[4] = hasFeature(VKP_FEATURE_ABSORPTION) ? texelFetch(materialsTexels, first + 4) : uvec4(0u);  // attenuation
    t[5] = hasFeature(VKP_FEATURE_SHEEN) ? texelFetch(materialsTexels, first + 5) : uvec4(0u);  // sheen
    t[6] = hasFeature(VKP_FEATURE_CLEARCOAT | VKP_FEATURE_DISPERSION) ? texelFetch(materialsTexels, first + 6) : uvec4(0u);  // clear coat, dispersion
    t[7] = hasFeature(VKP_FEATURE_DIFFUSE_TRANSMISSION) ? texelFetch(materialsTexels, first + 7)
                                                        : uvec4(0u);  // diffuse transmission
    t[8] = hasFeature(VKP_FEATURE_IRIDESCENCE) ? texelFetch(materialsTexels, first + 8) : uvec4(0u);  // thin film
    t[9] = hasFeature(VKP_FEATURE_ANISOTROPY) ? texelFetch(materialsTexels, first + 9) : uvec4(0u);  // anisotropy
    t[10] = uvec4(0u);  // the coat's normal: per hit only
    Material r;
    VKP_RECORD_DECODE(VKP_MATERIAL_FIELDS)
    return r;
}
MaterialAlpha sceneMaterialAlpha(uint i) {
    uvec4 t[1] = uvec4[1](texelFetch(materialAlphaTexels, int(i)));
    MaterialAlpha r;
    VKP_RECORD_DECODE(VKP_MATERIAL_ALPHA_FIELDS)
    return r;
}
Light sceneLight(uint i) {
    if (sceneByAddress) return LightArray(sceneAddresses.lights).v[i];
    int first = int(5u * i);
    uvec4 t[5] = uvec4[5](texelFetch(lightsTexels, first), texelFetch(lightsTexels, first + 1),
                          texelFetch(lightsTexels, first + 2), texelFetch(lightsTexels, first + 3),
                          texelFetch(lightsTexels, first + 4));
    Light r;
    VKP_RECORD_DECODE(VKP_LIGHT_FIELDS)
    return r;
}
AliasEntry aliasEntry(uvec4 texel) {
    uvec4 t[1] = uvec4[1](texel);
    AliasEntry r;
    VKP_RECORD_DECODE(VKP_ALIAS_ENTRY_FIELDS)
    return r;
}
AliasEntry sceneLightAlias(uint i) {
    if (sceneByAddress) return AliasArray(sceneAddresses.lightAlias).v[i];
    return aliasEntry(texelFetch(lightAliasTexels, int(i)));
}
// Four floats to a texel.
float sceneMicrofacetAlbedo(uint i) {
    uvec4 t = texelFetch(microfacetAlbedoTexels, int(i >> 2u));
    uint j = i & 3u;
    return uintBitsToFloat(j == 0u ? t.x : j == 1u ? t.y : j == 2u ? t.z : t.w);
}
LightTreeNode sceneLightTreeNode(uint i) {
    if (sceneByAddress) return LightTreeNodeArray(sceneAddresses.lightTree).v[i];
    int first = int(4u * i);
    uvec4 t[4] = uvec4[4](texelFetch(lightTreeTexels, first), texelFetch(lightTreeTexels, first + 1),
                          texelFetch(lightTreeTexels, first + 2), texelFetch(lightTreeTexels, first + 3));
    LightTreeNode r;
    VKP_RECORD_DECODE(VKP_LIGHT_TREE_NODE_FIELDS)
    return r;
}
Medium sceneMedium(uint i) {
    int first = int(2u * i);
    uvec4 t[2] = uvec4[2](texelFetch(mediaTexels, first), texelFetch(mediaTexels, first + 1));
    Medium r;
    VKP_RECORD_DECODE(VKP_MEDIUM_FIELDS)
    return r;
}
GridMedium sceneGridMedium() {
    uvec4 t[5] = uvec4[5](texelFetch(gridMediumTexels, 0), texelFetch(gridMediumTexels, 1),
                          texelFetch(gridMediumTexels, 2), texelFetch(gridMediumTexels, 3),
                          texelFetch(gridMediumTexels, 4));
    GridMedium r;
    VKP_RECORD_DECODE(VKP_GRID_MEDIUM_FIELDS)
    return r;
}
// Four floats to a texel.
float sceneGridDensity(uint i) {
    if (sceneByAddress) return FloatArray(sceneAddresses.gridDensity).v[i];
    uvec4 t = texelFetch(gridDensityTexels, int(i >> 2u));
    uint j = i & 3u;
    return uintBitsToFloat(j == 0u ? t.x : j == 1u ? t.y : j == 2u ? t.z : t.w);
}
float sceneGridMajorant(uint i) {
    if (sceneByAddress) return FloatArray(sceneAddresses.gridMajorant).v[i];
    uvec4 t = texelFetch(gridMajorantTexels, int(i >> 2u));
    uint j = i & 3u;
    return uintBitsToFloat(j == 0u ? t.x : j == 1u ? t.y : j == 2u ? t.z : t.w);
}
uint sceneLightTreeTrail(uint i) {
    if (sceneByAddress) return UintArray(sceneAddresses.lightTreeTrail).v[i];
    uvec4 t = texelFetch(lightTreeTrailTexels, int(i >> 2u));
    uint j = i & 3u;
    return j == 0u ? t.x : j == 1u ? t.y : j == 2u ? t.z : t.w;
}
uint scenePrimitiveLight(uint i) {
    if (sceneByAddress) return UintArray(sceneAddresses.primitiveLight).v[i];
    uvec4 t = texelFetch(primitiveLightTexels, int(i >> 2u));
    uint j = i & 3u;
    return j == 0u ? t.x : j == 1u ? t.y : j == 2u ? t.z : t.w;
}
AliasEntry sceneEnvAlias(uint i) {
    if (sceneByAddress) return AliasArray(sceneAddresses.envAlias).v[i];
    return aliasEntry(texelFetch(envAliasTexels, int(i)));
}
vec3 sceneEnvRadiance(uint i) {
    if (sceneByAddress) return Vec4Array(sceneAddresses.envRadiance).v[i].xyz;
    return uintBitsToFloat(texelFetch(envRadianceTexels, int(i)).xyz);
}
TriangleVertices sceneTriangleVertices(uint i) {
    if (sceneByAddress) return TriangleVerticesArray(sceneAddresses.triangleVertices).v[i];
    uvec4 t[1] = uvec4[1](texelFetch(triangleVerticesTexels, int(i)));
    TriangleVertices r;
    VKP_RECORD_DECODE(VKP_TRIANGLE_VERTICES_FIELDS)
    return r;
}
vec3 sceneVertexNormal(uint i) {
    if (sceneByAddress) return Vec4Array(sceneAddresses.vertexNormals).v[i].xyz;
    return uintBitsToFloat(texelFetch(vertexNormalsTexels, int(i)).xyz);
}
vec4 sceneVertexTexcoords(uint i) {
    if (sceneByAddress) return Vec4Array(sceneAddresses.vertexTexcoords).v[i];
    return uintBitsToFloat(texelFetch(vertexTexcoordsTexels, int(i)));
}
vec4 sceneVertexColor(uint i) {
    if (sceneByAddress) return Vec4Array(sceneAddresses.vertexColors).v[i];
    return uintBitsToFloat(texelFetch(vertexColorsTexels, int(i)));
}
vec4 sceneVertexTangent(uint i) {
    if (sceneByAddress) return Vec4Array(sceneAddresses.vertexTangents).v[i];
    return uintBitsToFloat(texelFetch(vertexTangentsTexels, int(i)));
}
TextureInfo sceneTexture(uint i) {
    uvec4 t[1] = uvec4[1](texelFetch(texturesTexels, int(i)));
    TextureInfo r;
    VKP_RECORD_DECODE(VKP_TEXTURE_INFO_FIELDS)
    return r;
}
TextureSlot sceneTextureSlot(uint i) {
    int first = int(3u * i);
    uvec4 t[3] = uvec4[3](texelFetch(textureSlotsTexels, first), texelFetch(textureSlotsTexels, first + 1),
                          texelFetch(textureSlotsTexels, first + 2));
    TextureSlot r;
    VKP_RECORD_DECODE(VKP_TEXTURE_SLOT_FIELDS)
    return r;
}
vec4 sceneTexel(uint i) {
    uvec2 packed;
    if (sceneByAddress) {
        packed = Uvec2Array(sceneAddresses.texels).v[i];
    } else {
        uvec4 t = texelFetch(texelsTexels, int(i >> 1u));
        packed = (i & 1u) == 0u ? t.xy : t.zw;
    }
    return vec4(unpackHalf2x16(packed.x), unpackHalf2x16(packed.y));
}

#include "shared/path_tracer.h"
#include "shared/integrator.h"
