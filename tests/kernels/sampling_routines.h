// The interface of tests/kernels/sampling_routines.comp, shared with the
// chi-square tests: which routine to run, its parameters, and one output
// record per sample.
#ifndef VKPATH_TESTS_SAMPLING_ROUTINES_H
#define VKPATH_TESTS_SAMPLING_ROUTINES_H

#include "shared/compat.h"

#define ROUTINE_COSINE_HEMISPHERE 0u
#define ROUTINE_UNIFORM_SPHERE 1u
#define ROUTINE_UNIFORM_HEMISPHERE 2u
#define ROUTINE_SPHERE_CONE 3u        // from point a toward sphere (centre b, radius scalar)
#define ROUTINE_TRIANGLE_AREA 4u      // triangle (a, b, c): writes barycentrics in direction.xy
#define ROUTINE_LAMBERTIAN 5u         // normal a, wo b, albedo 1
#define ROUTINE_DIELECTRIC 6u         // normal a, wo b, ior scalar
#define ROUTINE_MIRROR 7u             // normal a, wo b
#define ROUTINE_HENYEY_GREENSTEIN 8u  // wo b, g scalar

VKP_NAMESPACE_BEGIN

struct SamplingPush {
    uint routine;
    uint count;
    uint seed;
    float scalar;
    vec3 a;
    vec3 b;
    vec3 c;
};

struct SamplingResult {
    vec3 direction;
    float pdf;
    vec3 weight;
    uint flags;  // bit 0: valid, bit 1: delta
};

VKP_NAMESPACE_END

#endif
