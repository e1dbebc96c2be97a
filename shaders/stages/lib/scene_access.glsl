// The scene's buffers and the accessors shared/path_tracer.h reads them
// through, then the path tracer itself: its per-vertex math and its loop
// (shared/integrator.h).
#include "shared/alpha.h"
#include "shared/bsdf.h"
#include "shared/path_state.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/mesh_attributes.h"
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
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer UintArray { uint v[]; };
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
// glass-and-diffuse box reads three of the five.
Material sceneMaterial(uint i) {
    int t = int(5u * i);
    uvec4 a = texelFetch(materialsTexels, t);
    uvec4 b = hasFeature(VKP_FEATURES_TRANSMITS | VKP_FEATURES_MICROFACET | VKP_FEATURE_REGULARIZE)
                  ? texelFetch(materialsTexels, t + 1) : uvec4(0u);  // transmittance (k, F0), ior
    uvec4 c = hasFeature(VKP_FEATURE_EMISSIVE_SURFACES | VKP_FEATURE_TEXTURES | VKP_FEATURE_NORMAL_MAPS)
                  ? texelFetch(materialsTexels, t + 2) : uvec4(0u);  // emission, textures
    uvec4 d = hasFeature(VKP_FEATURES_MICROFACET | VKP_FEATURE_REGULARIZE)
                  ? texelFetch(materialsTexels, t + 3) : uvec4(0u);  // roughness, metallic, specular, flags
    uvec4 e = hasFeature(VKP_FEATURE_ABSORPTION) ? texelFetch(materialsTexels, t + 4) : uvec4(0u);  // attenuation
    Material m;
    m.reflectance = uintBitsToFloat(a.xyz);
    m.kind = a.w;
    m.transmittance = uintBitsToFloat(b.xyz);
    m.ior = uintBitsToFloat(b.w);
    m.emission = uintBitsToFloat(c.xyz);
    m.textures = c.w;
    m.roughness = uintBitsToFloat(d.x);
    m.metallic = uintBitsToFloat(d.y);
    m.specular = uintBitsToFloat(d.z);
    m.flags = d.w;
    m.attenuation = uintBitsToFloat(e.xyz);
    m.padding = e.w;
    return m;
}
MaterialAlpha sceneMaterialAlpha(uint i) {
    uvec4 t = texelFetch(materialAlphaTexels, int(i));
    MaterialAlpha m;
    m.mode = t.x;
    m.cutoff = uintBitsToFloat(t.y);
    m.alpha = uintBitsToFloat(t.z);
    m.baseColorSlot = t.w;
    return m;
}
Light sceneLight(uint i) {
    if (sceneByAddress) return LightArray(sceneAddresses.lights).v[i];
    int t = int(5u * i);
    uvec4 a = texelFetch(lightsTexels, t), b = texelFetch(lightsTexels, t + 1), c = texelFetch(lightsTexels, t + 2),
          d = texelFetch(lightsTexels, t + 3), e = texelFetch(lightsTexels, t + 4);
    Light light;
    light.p0 = uintBitsToFloat(a.xyz);
    light.type = a.w;
    light.p1 = uintBitsToFloat(b.xyz);
    light.radius = uintBitsToFloat(b.w);
    light.p2 = uintBitsToFloat(c.xyz);
    light.cosInner = uintBitsToFloat(c.w);
    light.emission = uintBitsToFloat(d.xyz);
    light.cosOuter = uintBitsToFloat(d.w);
    light.normal = uintBitsToFloat(e.xyz);
    light.area = uintBitsToFloat(e.w);
    return light;
}
AliasEntry aliasEntry(uvec4 t) {
    AliasEntry entry;
    entry.threshold = t.x;
    entry.alias = t.y;
    entry.probability = uintBitsToFloat(t.z);
    entry.padding = t.w;
    return entry;
}
AliasEntry sceneLightAlias(uint i) {
    if (sceneByAddress) return AliasArray(sceneAddresses.lightAlias).v[i];
    return aliasEntry(texelFetch(lightAliasTexels, int(i)));
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
    uvec4 t = texelFetch(triangleVerticesTexels, int(i));
    TriangleVertices v;
    v.vertex = t.xyz;
    v.attributes = t.w;
    return v;
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
    uvec4 t = texelFetch(texturesTexels, int(i));
    TextureInfo texture;
    texture.firstTexel = t.x;
    texture.width = t.y;
    texture.height = t.z;
    texture.sampling = t.w;
    return texture;
}
TextureSlot sceneTextureSlot(uint i) {
    int t = int(3u * i);
    uvec4 a = texelFetch(textureSlotsTexels, t), b = texelFetch(textureSlotsTexels, t + 1),
          c = texelFetch(textureSlotsTexels, t + 2);
    TextureSlot slot;
    slot.transformU = uintBitsToFloat(a.xyz);
    slot.texture = a.w;
    slot.transformV = uintBitsToFloat(b.xyz);
    slot.texCoord = b.w;
    slot.scale = uintBitsToFloat(c.x);
    slot.padding = c.yzw;
    return slot;
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
