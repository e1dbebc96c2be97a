// The feature sets the CPU reference's integrator is compiled for, beside the
// general code: the C++ counterpart of the GPU's specialised pipelines. A GPU
// kernel is specialised to a scene's exact features when its pipeline is
// built; C++ is compiled ahead of time, so the reference renderer carries a
// build of the shared code per profile below and runs the first whose
// features hold the render's (reference/path_sampler.h makePathSampler), the
// general build when none does or with --no-specialize. Each profile is one translation unit,
// cpu_profile_NAME.cpp:
//
//   #define VKP_CPU_FEATURES VKP_CPU_PROFILE_SMOOTH   // before any include
//   #include "reference/cpu_profiles.h"
//   #include "reference/path_sampler_of.h"
//
// There the shared functions are static (shared/compat.h VKP_FN) and
// shared::kernelFeatures is the profile's bits, so the compiler removes the
// code of every feature outside it, as the pipeline compiler does with the
// specialisation constant. A profile gains what the code it leaves out cost
// (docs/BENCHMARKS.md, "The CPU reference specialised (feature profiles)",
// which also has the profiles that kept the microfacet materials: they
// gained nothing and are not built, the gain is in leaving that code out).
//
// Only macros here, no includes: a profile's translation unit reads this
// header before shared/features.h defines the bits the masks name.
#ifndef VKPATH_REFERENCE_CPU_PROFILES_H
#define VKPATH_REFERENCE_CPU_PROFILES_H

// Smooth materials (Lambertian, mirror, glass) without textures: every
// Scotty3D scene and the bundled cornell_box_diffuse (a glTF metal is a
// conductor, even a smooth one: outside it). Any light, environment, sampler
// and light-sample count; interpolated normals; a BVH of any depth (the
// wide tree's traversal does not ask); sphere guiding. Leaves out the microfacet
// materials, textures, vertex colours, normal maps, alpha, path
// regularisation and absorption.
#define VKP_CPU_PROFILE_SMOOTH                                                                     \
    (VKP_FEATURES_PRIMITIVES | VKP_FEATURE_DIFFUSE | VKP_FEATURE_MIRROR | VKP_FEATURE_DIELECTRIC | \
     VKP_FEATURE_EMISSIVE_SURFACES | VKP_FEATURE_POINT_LIGHTS | VKP_FEATURE_SPOT_LIGHTS |          \
     VKP_FEATURE_DIRECTIONAL_LIGHTS | VKP_FEATURES_ENVIRONMENT | VKP_FEATURE_SAMPLER_INDEPENDENT | \
     VKP_FEATURE_SAMPLER_SOBOL | VKP_FEATURE_LIGHT_SAMPLES | VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES |  \
     VKP_FEATURE_ROULETTE | VKP_FEATURE_SHADING_NORMALS | VKP_FEATURE_DEEP_BVH |                   \
     VKP_FEATURE_SPHERE_GUIDING)

// The same with the albedo and normal AOVs (--aov albedo,normal, and
// --denoise's guides): a render without them keeps the profile above, whose
// code has none of theirs.
#define VKP_CPU_PROFILE_SMOOTH_AOVS (VKP_CPU_PROFILE_SMOOTH | VKP_FEATURE_AOVS)

// Everything but participating media and glTF's material extensions (the
// coat, sheen, thin wall, diffuse transmission, thin film, anisotropy and
// dispersion): the
// microfacet materials, textures, normal maps, alpha, instances,
// regularisation, the light tree and the AOVs. Without it such scenes ran
// the general build, which those features' code made 0.82x as fast on the
// bundled cornell_box (docs/BENCHMARKS.md, "glTF's material extensions:
// what they cost").
#define VKP_CPU_PROFILE_CORE                                                                     \
    ((VKP_FEATURE_BIT(VKP_FEATURE_COUNT) - 1u) &                                                 \
     ~(VKP_FEATURE_MEDIA | VKP_FEATURE_GRID_MEDIUM | VKP_FEATURE_CLEARCOAT | VKP_FEATURE_SHEEN | \
       VKP_FEATURE_THIN_WALLED | VKP_FEATURE_DIFFUSE_TRANSMISSION | VKP_FEATURE_IRIDESCENCE |    \
       VKP_FEATURE_ANISOTROPY | VKP_FEATURE_DISPERSION))

#endif  // VKPATH_REFERENCE_CPU_PROFILES_H
