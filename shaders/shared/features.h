// What a kernel may meet: one bit per feature of a scene and its render
// settings. A pipeline is built with the bits of the scene it renders
// (specialisation constant VKP_SPEC_FEATURES, host/wavefront/kernel_features),
// and the shared code asks hasFeature() before every piece of work that a
// feature needs, so the pipeline compiler folds the tests of absent features
// to constants and drops their code: a diffuse-only box runs no glass, sphere,
// environment or Sobol' code. A set bit means "may occur", never "occurs":
// VKP_FEATURES_ALL is the general kernel (--no-specialize), and a scene
// renders bit for bit the same with its own bits as with all of them (only
// code that the scene's data would never take is removed;
// tests/render/all_scenes_test.cpp, EveryKernelGivesTheSameImage).
//
// Rules for adding a feature (textures, normal maps, microfacet lobes...):
// one bit here, one line in host/wavefront/kernel_features.cpp that sets it
// from the scene tables or settings, and hasFeature() around its code. A
// feature that reads a Material field adds its bit to the condition under
// which stages/lib/scene_access.glsl sceneMaterial fetches that field's texel
// (a kernel without it reads the field as zero). The CPU reference's
// profiles (host/reference/cpu_profiles.h) hold a new bit only once it is
// added to one: until then a scene with it runs the general build.
#ifndef VKPATH_SHARED_FEATURES_H
#define VKPATH_SHARED_FEATURES_H

#include "shared/bindings.h"
#include "shared/compat.h"
#include "shared/material_kinds.h"

#define VKP_FEATURE_TRIANGLES (1u << 0)
#define VKP_FEATURE_SPHERES (1u << 1)
// Bits 2, 3, 4, 20, 21 and 22: the material kinds' (shared/material_kinds.h),
// VKP_FEATURE_DIFFUSE, _MIRROR, _DIELECTRIC, _CONDUCTOR, _ROUGH_DIELECTRIC and
// _METALLIC_ROUGHNESS, defined below from the registry.
#define VKP_FEATURE_EMISSIVE_SURFACES (1u << 5)  // a primitive with a material that emits
#define VKP_FEATURE_POINT_LIGHTS (1u << 6)
#define VKP_FEATURE_SPOT_LIGHTS (1u << 7)
#define VKP_FEATURE_DIRECTIONAL_LIGHTS (1u << 8)
#define VKP_FEATURE_ENVIRONMENT_COLOR (1u << 9)  // a constant environment
#define VKP_FEATURE_ENVIRONMENT_MAP (1u << 10)   // an environment map
#define VKP_FEATURE_SAMPLER_INDEPENDENT (1u << 11)
#define VKP_FEATURE_SAMPLER_SOBOL (1u << 12)
#define VKP_FEATURE_LIGHT_SAMPLES (1u << 13)  // SceneInfo::lightSamples > 0: next-event estimation
#define VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES (1u << 14)  // SceneInfo::lightSamples > 1
#define VKP_FEATURE_ROULETTE (1u << 15)  // rouletteDepth <= maxDepth: roulette can end a path
#define VKP_FEATURE_SHADING_NORMALS (1u << 16)  // a triangle with interpolated vertex normals
#define VKP_FEATURE_TEXTURES (1u << 17)         // a material with a texture
#define VKP_FEATURE_VERTEX_COLORS (1u << 18)    // a triangle with vertex colours
#define VKP_FEATURE_NORMAL_MAPS (1u << 19)      // a triangle with a normal map and tangents
#define VKP_FEATURE_ALPHA (1u << 23)       // a triangle whose material may leave holes (alphaMode)
#define VKP_FEATURE_REGULARIZE (1u << 24)  // path regularisation (SceneInfo::regularizeAlpha > 0)
#define VKP_FEATURE_ABSORPTION \
    (1u << 25)  // a primitive of glass that absorbs inside (attenuation > 0)
#define VKP_FEATURE_DEEP_BVH \
    (1u << 26)  // a BVH leaf below depth VKP_BVH_SHALLOW_DEPTH (the stack spills to an array)
#define VKP_FEATURE_SPHERE_GUIDING \
    (1u << 27)  // diffuse samples guided toward smooth specular spheres
// --aov albedo,normal (SceneInfo::aovs): each path keeps the albedo and
// shading normal of its first non-delta hit (shared/integrator.h recordAov)
#define VKP_FEATURE_AOVS (1u << 28)
// A mesh stored once and placed by instances (shared/bvh.h): the scene's
// tree has instance primitives, whose bottom-level trees traversal enters
#define VKP_FEATURE_INSTANCES (1u << 29)
// Multiple-scattering compensation of the microfacet lobes
// (SceneInfo::microfacetCompensation, shared/microfacet_albedo.h): a kind
// with a GGX lobe may occur and the render compensates
#define VKP_FEATURE_MICROFACET_COMPENSATION (1u << 30)
#define VKP_FEATURE_COUNT 31u

#define VKP_FEATURES_ALL 0xffffffffu
// Each material kind's bit, VKP_FEATURE_<its NAME>, from the registry.
#define VKP_KIND_FEATURE_CONSTANT(id, NAME, Type, key, label, feature, flags, regularized) \
    VKP_CONSTANT(VKP_FEATURE_##NAME, feature)
VKP_MATERIAL_KINDS(VKP_KIND_FEATURE_CONSTANT)
#undef VKP_KIND_FEATURE_CONSTANT
// The material kinds' bits, from their registry (shared/material_kinds.h).
#define VKP_FEATURES_MATERIALS (0u VKP_MATERIAL_KINDS(VKP_KIND_FEATURE_TERM))
// The materials with a GGX lobe: they read Material::roughness (and the metallic-roughness
// texture).
#define VKP_FEATURES_MICROFACET (0u VKP_MATERIAL_KINDS(VKP_KIND_MICROFACET_TERM))
// The materials that may have a non-delta lobe: light samples may be traced from them.
#define VKP_FEATURES_NON_DELTA (0u VKP_MATERIAL_KINDS(VKP_KIND_NON_DELTA_TERM))
// The glass kinds: they read Material::ior and transmittance.
#define VKP_FEATURES_TRANSMITS (0u VKP_MATERIAL_KINDS(VKP_KIND_TRANSMITS_TERM))
#define VKP_FEATURES_PRIMITIVES \
    (VKP_FEATURE_TRIANGLES | VKP_FEATURE_SPHERES | VKP_FEATURE_INSTANCES)
#define VKP_FEATURES_ENVIRONMENT (VKP_FEATURE_ENVIRONMENT_COLOR | VKP_FEATURE_ENVIRONMENT_MAP)

VKP_NAMESPACE_BEGIN

#ifdef __cplusplus
// C++ compiles the general code (each test a branch on data) unless the
// translation unit defines VKP_CPU_FEATURES before its first include: the
// CPU reference's integrator compiled for a feature profile
// (host/reference/cpu_profiles.h), whose functions are then its own
// (shared/compat.h VKP_FN).
#ifdef VKP_CPU_FEATURES
constexpr uint kernelFeatures = VKP_CPU_FEATURES;
#else
constexpr uint kernelFeatures = VKP_FEATURES_ALL;
#endif
#else
layout(constant_id = VKP_SPEC_FEATURES) const uint kernelFeatures = VKP_FEATURES_ALL;
#endif

// Whether any of `features` may occur.
VKP_FN bool hasFeature(uint features) {
    return (kernelFeatures & features) != 0u;
}

// Whether `feature` is the only one of `group` that may occur (so a test
// between the members of the group is known without reading data).
VKP_FN bool onlyFeature(uint group, uint feature) {
    return (kernelFeatures & group) == feature;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_FEATURES_H
