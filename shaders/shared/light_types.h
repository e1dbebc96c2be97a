// The registry of light types: the one list of them, read by GLSL and C++.
// From it come the VKP_LIGHT_* numbers (Light::type, shared/lights.h), the
// types a kernel may meet from its features (possibleLightTypes), the
// dispatch of a light sample to its type (sampleLight) and the host's
// feature bits of the lights a scene lists (host/wavefront/kernel_features).
// tests/kernels/light_registry_test.cpp walks it.
//
// One row per type:
//
//   X(ID, NAME, Type, "label", FEATURE, SHAPE, FLAGS)
//
//   ID       Light::type, 0 to VKP_LIGHT_TYPE_COUNT - 1 in order
//   NAME     VKP_LIGHT_NAME, the kernels' constant
//   Type     the stem of its sampling function in shared/lights.h,
//            sampleTypeLight(light, p, u)
//   "label"  its name in logs and tests
//   FEATURE  the feature bits (shared/features.h) under which a kernel may
//            meet it: kernels without any compile none of its code
//   SHAPE    for area lights, the primitive's feature bit, also required;
//            VKP_NO_FEATURES for the others
//   FLAGS    VKP_LIGHT_IS_* below
//
// Adding a type: a row here (the next ID), its feature bit in
// shared/features.h (unless an existing one covers it), its sampling function
// in shared/lights.h, its device record and power in
// host/wavefront/gpu_scene.cpp (one function per type), its scene model and
// importers, and its Mitsuba export. docs/ARCHITECTURE.md, "Adding a light
// type", is the checklist.
#ifndef VKPATH_SHARED_LIGHT_TYPES_H
#define VKPATH_SHARED_LIGHT_TYPES_H

#define VKP_LIGHT_IS_AREA 1u  // an emissive primitive: sampled by area, hit by BSDF samples (MIS)
#define VKP_LIGHT_IS_DELTA \
    2u  // a point or a direction: never hit, no MIS; listed in the scene's lights
// Light at infinity: no position, so outside the light tree (shared/light_tree.h); listed after
// every bounded light
#define VKP_LIGHT_IS_INFINITE 4u

#define VKP_LIGHT_TYPES(X)                                                                      \
    X(0u, TRIANGLE, Triangle, "triangle", VKP_FEATURE_EMISSIVE_SURFACES, VKP_FEATURE_TRIANGLES, \
      VKP_LIGHT_IS_AREA)                                                                        \
    X(1u, SPHERE, Sphere, "sphere", VKP_FEATURE_EMISSIVE_SURFACES, VKP_FEATURE_SPHERES,         \
      VKP_LIGHT_IS_AREA)                                                                        \
    X(2u, POINT, Point, "point", VKP_FEATURE_POINT_LIGHTS, VKP_NO_FEATURES, VKP_LIGHT_IS_DELTA) \
    X(3u, SPOT, Spot, "spot", VKP_FEATURE_SPOT_LIGHTS, VKP_NO_FEATURES, VKP_LIGHT_IS_DELTA)     \
    X(4u, DIRECTIONAL, Directional, "directional", VKP_FEATURE_DIRECTIONAL_LIGHTS,              \
      VKP_NO_FEATURES, VKP_LIGHT_IS_DELTA | VKP_LIGHT_IS_INFINITE)                              \
    /* sampled by its caller, which holds its table (shared/environment_sampling.h) */          \
    X(5u, ENVIRONMENT, Environment, "environment", VKP_FEATURES_ENVIRONMENT, VKP_NO_FEATURES,   \
      VKP_LIGHT_IS_INFINITE)

#define VKP_LIGHT_TYPE_COUNT 6u

#endif  // VKPATH_SHARED_LIGHT_TYPES_H
