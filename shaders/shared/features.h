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
// (a kernel without it reads the field as zero). Ask hasFeature() of a
// constant mask (VKP_FEATURE_* and expressions of them): a feature profile's
// build removes the code behind such tests only. The feature profiles
// (shared/feature_profiles.h), which the GPU kernels and the CPU reference
// are compiled for, hold a new bit only once it is added to one: until then
// a scene with it runs the general code.
#ifndef VKPATH_SHARED_FEATURES_H
#define VKPATH_SHARED_FEATURES_H

#include "shared/bindings.h"
#include "shared/compat.h"

// A set of feature bits, 64 of them: FeatureMask (uint64_t), bit n
// VKP_FEATURE_BIT(n). GLSL's 64-bit integers need the extension below and the
// device feature shaderInt64 (vk/context.cpp requires it); with them every
// feature test stays one scalar expression of specialisation constants, as
// with the 32-bit mask before (a uvec2 mask would fold a vector == into
// OpAll, which a specialisation constant may not use).
#ifdef __cplusplus
#define VKP_FEATURE_BIT(n) (uint64_t{1} << (n))
#define VKP_NO_FEATURES (uint64_t(0))
#define VKP_FEATURES_ALL (~uint64_t(0))
// A named feature mask at file scope (VKP_CONSTANT's for masks).
#define VKP_FEATURE_CONSTANT(name, value) inline constexpr uint64_t name = value;
#else
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#define FeatureMask uint64_t
#define VKP_FEATURE_BIT(n) (1ul << (n))
#define VKP_NO_FEATURES 0ul
#define VKP_FEATURES_ALL 0xfffffffffffffffful
#define VKP_FEATURE_CONSTANT(name, value) const uint64_t name = value;
#endif

#include "shared/feature_profiles.h"
#include "shared/material_kinds.h"

#define VKP_FEATURE_TRIANGLES VKP_FEATURE_BIT(0)
#define VKP_FEATURE_SPHERES VKP_FEATURE_BIT(1)
// Bits 2, 3, 4, 20, 21 and 22: the material kinds' (shared/material_kinds.h),
// VKP_FEATURE_DIFFUSE, _MIRROR, _DIELECTRIC, _CONDUCTOR, _ROUGH_DIELECTRIC and
// _METALLIC_ROUGHNESS, defined below from the registry.
#define VKP_FEATURE_EMISSIVE_SURFACES VKP_FEATURE_BIT(5)  // a primitive with a material that emits
#define VKP_FEATURE_POINT_LIGHTS VKP_FEATURE_BIT(6)
#define VKP_FEATURE_SPOT_LIGHTS VKP_FEATURE_BIT(7)
#define VKP_FEATURE_DIRECTIONAL_LIGHTS VKP_FEATURE_BIT(8)
#define VKP_FEATURE_ENVIRONMENT_COLOR VKP_FEATURE_BIT(9)  // a constant environment
#define VKP_FEATURE_ENVIRONMENT_MAP VKP_FEATURE_BIT(10)   // an environment map
#define VKP_FEATURE_SAMPLER_INDEPENDENT VKP_FEATURE_BIT(11)
#define VKP_FEATURE_SAMPLER_SOBOL VKP_FEATURE_BIT(12)
#define VKP_FEATURE_LIGHT_SAMPLES \
    VKP_FEATURE_BIT(13)  // SceneInfo::lightSamples > 0: next-event estimation
#define VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES VKP_FEATURE_BIT(14)  // SceneInfo::lightSamples > 1
#define VKP_FEATURE_ROULETTE \
    VKP_FEATURE_BIT(15)  // rouletteDepth <= maxDepth: roulette can end a path
#define VKP_FEATURE_SHADING_NORMALS \
    VKP_FEATURE_BIT(16)                           // a triangle with interpolated vertex normals
#define VKP_FEATURE_TEXTURES VKP_FEATURE_BIT(17)  // a material with a texture
#define VKP_FEATURE_VERTEX_COLORS VKP_FEATURE_BIT(18)  // a triangle with vertex colours
#define VKP_FEATURE_NORMAL_MAPS VKP_FEATURE_BIT(19)    // a triangle with a normal map and tangents
#define VKP_FEATURE_ALPHA \
    VKP_FEATURE_BIT(23)  // a triangle whose material may leave holes (alphaMode)
#define VKP_FEATURE_REGULARIZE \
    VKP_FEATURE_BIT(24)  // path regularisation (SceneInfo::regularizeAlpha > 0)
#define VKP_FEATURE_ABSORPTION \
    VKP_FEATURE_BIT(25)  // a primitive of glass that absorbs inside (attenuation > 0)
// A BVH leaf below depth VKP_BVH_SHALLOW_DEPTH (the stack spills to an array)
#define VKP_FEATURE_DEEP_BVH VKP_FEATURE_BIT(26)
#define VKP_FEATURE_SPHERE_GUIDING \
    VKP_FEATURE_BIT(27)  // diffuse samples guided toward smooth specular spheres
// --aov albedo,normal (SceneInfo::aovs): each path keeps the albedo and
// shading normal of its first non-delta hit (shared/integrator.h recordAov)
#define VKP_FEATURE_AOVS VKP_FEATURE_BIT(28)
// A mesh stored once and placed by instances (shared/bvh.h): the scene's
// tree has instance primitives, whose bottom-level trees traversal enters
#define VKP_FEATURE_INSTANCES VKP_FEATURE_BIT(29)
// Multiple-scattering compensation of the microfacet lobes
// (SceneInfo::microfacetCompensation, shared/microfacet_albedo.h): a kind
// with a GGX lobe may occur and the render compensates
#define VKP_FEATURE_MICROFACET_COMPENSATION VKP_FEATURE_BIT(30)
// Lights chosen through the light tree (SceneInfo::treeLights,
// shared/light_tree.h), not by power alone
#define VKP_FEATURE_LIGHT_TREE VKP_FEATURE_BIT(31)
// A point or spot light with a range (KHR_lights_punctual; Light::radius,
// shared/lights.h rangeWindow)
#define VKP_FEATURE_LIGHT_RANGE VKP_FEATURE_BIT(32)
// A participating medium: the fog or a transmitting material's inside that
// scatters (SceneInfo::media, shared/medium.h)
#define VKP_FEATURE_MEDIA VKP_FEATURE_BIT(33)
// The grid medium of render --volume (SceneInfo::gridMedium): heterogeneous,
// delta and ratio tracking over its majorant cells (shared/path/media.h)
#define VKP_FEATURE_GRID_MEDIUM VKP_FEATURE_BIT(34)
// A metallic-roughness material with a clear coat (KHR_materials_clearcoat;
// Material::clearcoat > 0, shared/metallic_roughness.h)
#define VKP_FEATURE_CLEARCOAT VKP_FEATURE_BIT(35)
// A metallic-roughness material with a sheen (KHR_materials_sheen;
// Material::sheenColor > 0, shared/sheen.h)
#define VKP_FEATURE_SHEEN VKP_FEATURE_BIT(36)
// A glass whose surface is a thin wall (KHR_materials_transmission without
// KHR_materials_volume; Material::flags VKP_MATERIAL_THIN_WALLED): light
// passes it unbent, and no inside lies behind it
#define VKP_FEATURE_THIN_WALLED VKP_FEATURE_BIT(37)
// A metallic-roughness material whose diffuse lobe passes light to its back
// (KHR_materials_diffuse_transmission; Material::diffuseTransmission > 0)
#define VKP_FEATURE_DIFFUSE_TRANSMISSION VKP_FEATURE_BIT(38)
// A metallic-roughness material under a thin film (KHR_materials_iridescence;
// Material::iridescence > 0, shared/thin_film.h)
#define VKP_FEATURE_IRIDESCENCE VKP_FEATURE_BIT(39)
// A microfacet material rougher along one direction of its surface than
// across it (KHR_materials_anisotropy; Material::anisotropy > 0)
#define VKP_FEATURE_ANISOTROPY VKP_FEATURE_BIT(40)
// Glass whose index varies with the wavelength (KHR_materials_dispersion;
// Material::dispersion > 0): paths that meet it follow one wavelength
// (shared/spectral.h), kept per path (PathState::wavelength)
#define VKP_FEATURE_DISPERSION VKP_FEATURE_BIT(41)
#define VKP_FEATURE_COUNT 42u  // bits 42 to 63 are free

// Each material kind's bit, VKP_FEATURE_<its NAME>, from the registry.
#define VKP_KIND_FEATURE_CONSTANT(id, NAME, Type, key, label, feature, flags, regularized) \
    VKP_FEATURE_CONSTANT(VKP_FEATURE_##NAME, feature)
VKP_MATERIAL_KINDS(VKP_KIND_FEATURE_CONSTANT)
#undef VKP_KIND_FEATURE_CONSTANT
// The material kinds' bits, from their registry (shared/material_kinds.h).
#define VKP_FEATURES_MATERIALS (VKP_NO_FEATURES VKP_MATERIAL_KINDS(VKP_KIND_FEATURE_TERM))
// The materials with a GGX lobe: they read Material::roughness (and the metallic-roughness
// texture).
#define VKP_FEATURES_MICROFACET (VKP_NO_FEATURES VKP_MATERIAL_KINDS(VKP_KIND_MICROFACET_TERM))
// The materials that may have a non-delta lobe: light samples may be traced from them.
#define VKP_FEATURES_NON_DELTA (VKP_NO_FEATURES VKP_MATERIAL_KINDS(VKP_KIND_NON_DELTA_TERM))
// The glass kinds: they read Material::ior and transmittance.
#define VKP_FEATURES_TRANSMITS (VKP_NO_FEATURES VKP_MATERIAL_KINDS(VKP_KIND_TRANSMITS_TERM))
#define VKP_FEATURES_PRIMITIVES \
    (VKP_FEATURE_TRIANGLES | VKP_FEATURE_SPHERES | VKP_FEATURE_INSTANCES)
#define VKP_FEATURES_ENVIRONMENT (VKP_FEATURE_ENVIRONMENT_COLOR | VKP_FEATURE_ENVIRONMENT_MAP)

VKP_NAMESPACE_BEGIN

#ifdef __cplusplus
using FeatureMask = uint64_t;
// C++ compiles the general code (each test a branch on data) unless the
// translation unit defines VKP_CPU_FEATURES before its first include: the
// CPU reference's integrator compiled for a feature profile
// (shared/feature_profiles.h), whose functions are then its own
// (shared/compat.h VKP_FN).
#ifdef VKP_CPU_FEATURES
constexpr FeatureMask kernelFeatures = VKP_CPU_FEATURES;
#else
constexpr FeatureMask kernelFeatures = VKP_FEATURES_ALL;
#endif

// Whether any of `features` may occur.
VKP_FN bool hasFeature(FeatureMask features) {
    return (kernelFeatures & features) != VKP_NO_FEATURES;
}
#else
// A kernel compiled for a feature profile (shared/feature_profiles.h) gets
// its mask from the build (-DVKP_PROFILE_FEATURES=VKP_FEATURE_PROFILE_CORE);
// the general kernel holds every bit.
#ifndef VKP_PROFILE_FEATURES
#define VKP_PROFILE_FEATURES VKP_FEATURES_ALL
#endif
// Two 32-bit constants, so that the host's specialisation entries stay 4 bytes.
layout(constant_id = VKP_SPEC_FEATURES) const uint kernelFeaturesLow = 0xffffffffu;
layout(constant_id = VKP_SPEC_FEATURES_HIGH) const uint kernelFeaturesHigh = 0xffffffffu;
const uint64_t kernelFeatures =
    (uint64_t(kernelFeaturesHigh) << 32 | uint64_t(kernelFeaturesLow)) & (VKP_PROFILE_FEATURES);

VKP_FN bool specializedHasFeature(FeatureMask features) {
    return (kernelFeatures & features) != VKP_NO_FEATURES;
}

// Whether any of `features` may occur. A macro, so that a bit outside the
// kernel's profile is a constant false before the call: glslang then branches
// on a constant, and the build's spirv-opt pass (cmake/shaders.cmake) removes
// that branch and, once it has inlined every call, the code only it reached.
// (A specialisation constant folds only in the driver, after it has
// translated the whole module; SPIRV-Tools folds no 64-bit operation.)
#define hasFeature(features) \
    (((VKP_PROFILE_FEATURES) & (features)) != VKP_NO_FEATURES && specializedHasFeature(features))
#endif

// Whether `feature` is the only one of `group` that may occur (so a test
// between the members of the group is known without reading data).
VKP_FN bool onlyFeature(FeatureMask group, FeatureMask feature) {
    return (kernelFeatures & group) == feature;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_FEATURES_H
