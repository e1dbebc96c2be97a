// The interface of tests/kernels/microfacet_routines.comp, shared with the
// microfacet tests: which lobe to sample, its parameters, and one output
// record per sample. Directions are in the local shading frame (normal +z).
#ifndef VKPATH_TESTS_MICROFACET_ROUTINES_H
#define VKPATH_TESTS_MICROFACET_ROUTINES_H

#include "shared/compat.h"

#define MICROFACET_VISIBLE_NORMAL 0u  // sampleGgxVisibleNormal(wo): direction = m, pdf = D_wo(m)
#define MICROFACET_CONDUCTOR 1u       // sampleConductor, with evalConductor / conductorPdf
#define MICROFACET_DIELECTRIC 2u      // sampleRoughDielectric, with its eval / pdf (tints 1)

VKP_NAMESPACE_BEGIN

struct MicrofacetPush {
    uint routine;  // MICROFACET_*
    uint count;    // samples
    uint seed;
    uint fresnel;  // conductor: VKP_FRESNEL_* (shared/microfacet.h)
    vec2 alpha;
    float ior;  // dielectric
    vec3 wo;    // local, unit
    vec3 f0;
    vec3 eta;
    vec3 k;
};

struct MicrofacetResult {
    vec3 direction;  // sampled wi (or m), local
    float pdf;       // the sampler's own density
    vec3 weight;     // BsdfSample::weight
    uint flags;      // bit 0: valid, bit 1: delta
    vec3 eval;       // the lobe's eval (f |cos wi|) at the sampled direction, on the GPU
    float evalPdf;   // the lobe's pdf function at the sampled direction, on the GPU
    float etaSquared;
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::MicrofacetPush) == 76);  // the scalar layout's size
static_assert(sizeof(vkpath::shared::MicrofacetResult) == 52);
#endif

#endif
