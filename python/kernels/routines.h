// The records of python/kernels/*.comp, the shared routines that the Python
// module runs over arrays (python/module.cpp): one push-constant block and one
// input and output record per routine, in the scalar layout.
#ifndef VKPATH_PYTHON_ROUTINES_H
#define VKPATH_PYTHON_ROUTINES_H

#include "shared/compat.h"
#include "shared/wavefront.h"

VKP_NAMESPACE_BEGIN

// bsdf_routine.comp: the material in binding 2 at each input's wo, in the
// local shading frame (geometric and shading normal +z).
struct BsdfRoutinePush {
    uint count;
    uint atSample;  // 1: evalBsdf and bsdfPdf at the sampled direction (0 where invalid), not wi
};

struct BsdfRoutineInput {
    vec3 wo;  // unit, toward the viewer
    vec3 wi;  // unit: where evalBsdf and bsdfPdf are evaluated
    vec3 u;   // sampleBsdf's numbers: u.xy the direction, u.z the lobe choice
};

struct BsdfRoutineOutput {
    vec3 direction;  // sampleBsdf's wi
    float pdf;       // its solid-angle density; a delta lobe's discrete probability
    vec3 weight;     // f |cos wi| / pdf
    uint flags;      // bit 0: valid, bit 1: delta
    vec3 eval;       // evalBsdf(wo, wi): f |cos wi|
    float evalPdf;   // bsdfPdf(wo, wi)
    float etaSquared;
};

// sampler_values.comp: rngUniform(key, dimension) of a sampler for every
// (sample, dimension, pixel), i = (sample * dimensions + dimension) * pixels + pixel.
struct SamplerValuesPush {
    uint count;
    uint pixels;
    uint dimensions;
    uint seed;
    uint samplerKind;  // VKP_SAMPLER_*
    uint firstSample;  // sample indices start here
};

// light_routine.comp: sampleSceneLight (shared/path/next_event.h) from each
// input's point, with the numbers of the key (input index, sampleIndex, seed,
// sampler) from dimension 0, and the environment's density and radiance
// (environmentPdf, environmentRadiance) in each input's direction. The scene's
// arrays are bound as the stage kernels bind them; these two beside them.
#define VKP_ROUTINE_INPUTS VKP_WF_FIRST_FREE_BINDING
#define VKP_ROUTINE_OUTPUTS (VKP_WF_FIRST_FREE_BINDING + 1)

struct LightRoutinePush {
    uint count;
    uint seed;
    uint samplerKind;  // VKP_SAMPLER_*
    uint sampleIndex;
};

struct LightRoutineInput {
    vec3 point;      // render space
    vec3 direction;  // unit
};

struct LightRoutineOutput {
    vec3 direction;  // toward the chosen light
    float distance;  // to the point on it; VKP_FLOAT_MAX for directional and environment
    vec3 radiance;   // LightSample::radiance
    float pdf;       // of the direction given the light (1 for a delta light)
    vec3 normal;     // at the point on an area light, else 0
    float choice;    // the probability of choosing the light
    uint lightIndex;
    uint delta;                // 1: a point, spot or directional light
    vec3 environmentRadiance;  // in the input's direction
    float environmentPdf;      // of the input's direction, given the environment is chosen
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::BsdfRoutinePush) == 8);  // the scalar layout's sizes
static_assert(sizeof(vkpath::shared::BsdfRoutineInput) == 36);
static_assert(sizeof(vkpath::shared::BsdfRoutineOutput) == 52);
static_assert(sizeof(vkpath::shared::SamplerValuesPush) == 24);
static_assert(sizeof(vkpath::shared::LightRoutineInput) == 24);
static_assert(sizeof(vkpath::shared::LightRoutineOutput) == 72);
#endif

#endif
