// Feature profiles: the feature sets (shared/features.h) that the shared code
// is compiled for ahead of time, beside the general code that holds every
// feature. A render runs the first profile, in the order of
// VKP_FEATURE_PROFILES, that holds its features, and the general code when
// none does or with --no-specialize.
//
// - GPU kernels (cmake/shaders.cmake, PROFILED): each profiled kernel is
//   compiled once per profile with VKP_PROFILE_FEATURES set to its mask, so
//   hasFeature() of a bit outside it is a constant false in the GLSL, and the
//   build's spirv-opt pass removes that code before the module is embedded
//   (megakernel_core, shade_smooth, ...; wavefront/kernel_features.h
//   profiledKernel). A driver translates a module's whole SPIR-V before
//   specialisation constants remove anything, so a smaller module is a
//   faster pipeline: docs/BENCHMARKS.md, "Start-up".
// - The CPU reference (host/reference/cpu_profile_KEY.cpp) compiles the
//   integrator once per profile with VKP_CPU_FEATURES set to its mask, so the
//   C++ compiler removes the code the GPU's specialisation would
//   (docs/BENCHMARKS.md, "The CPU reference specialised (feature profiles)").
//
// Only macros here, no includes: the masks name bits that shared/features.h
// defines, and a translation unit may read this header before it.
#ifndef VKPATH_SHARED_FEATURE_PROFILES_H
#define VKPATH_SHARED_FEATURE_PROFILES_H

// Smooth materials (Lambertian, mirror, glass) without textures: every
// Scotty3D scene and the bundled cornell_box_diffuse (a glTF metal is a
// conductor, even a smooth one: outside it). Any light, environment, sampler
// and light-sample count; interpolated normals; a BVH of any depth; sphere
// guiding. Leaves out the microfacet materials, textures, vertex colours,
// normal maps, alpha, path regularisation and absorption.
#define VKP_FEATURE_PROFILE_SMOOTH                                                                 \
    (VKP_FEATURES_PRIMITIVES | VKP_FEATURE_DIFFUSE | VKP_FEATURE_MIRROR | VKP_FEATURE_DIELECTRIC | \
     VKP_FEATURE_EMISSIVE_SURFACES | VKP_FEATURE_POINT_LIGHTS | VKP_FEATURE_SPOT_LIGHTS |          \
     VKP_FEATURE_DIRECTIONAL_LIGHTS | VKP_FEATURES_ENVIRONMENT | VKP_FEATURE_SAMPLER_INDEPENDENT | \
     VKP_FEATURE_SAMPLER_SOBOL | VKP_FEATURE_LIGHT_SAMPLES | VKP_FEATURE_MULTIPLE_LIGHT_SAMPLES |  \
     VKP_FEATURE_ROULETTE | VKP_FEATURE_SHADING_NORMALS | VKP_FEATURE_DEEP_BVH |                   \
     VKP_FEATURE_SPHERE_GUIDING)

// The same with the albedo and normal AOVs (--aov albedo,normal, and
// --denoise's guides): a render without them keeps the profile above, whose
// code has none of theirs.
#define VKP_FEATURE_PROFILE_SMOOTH_AOVS (VKP_FEATURE_PROFILE_SMOOTH | VKP_FEATURE_AOVS)

// Everything but participating media and glTF's material extensions (the
// coat, sheen, thin wall, diffuse transmission, thin film, anisotropy and
// dispersion): the microfacet materials, textures, normal maps, alpha,
// instances, regularisation, the light tree and the AOVs. Without it such
// scenes ran the general code, which those features' code made 0.82x as fast
// on the bundled cornell_box on the CPU (docs/BENCHMARKS.md, "glTF's material
// extensions: what they cost") and 2.3 times slower to compile on lavapipe.
#define VKP_FEATURE_PROFILE_CORE                                                                 \
    ((VKP_FEATURE_BIT(VKP_FEATURE_COUNT) - 1u) &                                                 \
     ~(VKP_FEATURE_MEDIA | VKP_FEATURE_GRID_MEDIUM | VKP_FEATURE_CLEARCOAT | VKP_FEATURE_SHEEN | \
       VKP_FEATURE_THIN_WALLED | VKP_FEATURE_DIFFUSE_TRANSMISSION | VKP_FEATURE_IRIDESCENCE |    \
       VKP_FEATURE_ANISOTROPY | VKP_FEATURE_DISPERSION))

// X(NAME, key, "label") for every profile, narrowest first: its mask is
// VKP_FEATURE_PROFILE_<NAME>, its kernels are named <kernel>_<key> (the build
// reads the keys from the lines below), and logs name it by its label.
// clang-format off
#define VKP_FEATURE_PROFILES(X) \
    X(SMOOTH, smooth, "smooth") \
    X(SMOOTH_AOVS, smooth_aovs, "smooth-aovs") \
    X(CORE, core, "core")
// clang-format on

#endif  // VKPATH_SHARED_FEATURE_PROFILES_H
