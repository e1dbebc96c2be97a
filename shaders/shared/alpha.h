// Alpha coverage (glTF 2.0 section 3.9.4 "Alpha Coverage"): a triangle whose
// material has alphaMode MASK or BLEND is only partly there, and the BVH
// traversal decides for each candidate hit whether the ray meets the surface
// or passes through it (shared/bvh_traverse.h asks bvhAlphaTest, which
// shared/path_tracer.h defines with the functions below). A point's alpha is
// the material's baseColorFactor alpha x the base-colour texture's alpha x
// COLOR_0's alpha, the alpha of the base colour that section 3.9.2 defines.
//
//   MASK   the point is there where alpha >= alphaCutoff, else a hole: a
//          deterministic test, the same for every ray.
//   BLEND  the point is there with probability alpha (stochastic
//          transparency: Enderton, Sintorn, Shirley and Luebke, "Stochastic
//          Transparency", I3D 2010; alpha as a coverage probability, as
//          pbrt-v4's alpha textures are). For one ray, candidates at
//          distances t1 < t2 < ... accepted independently with probabilities
//          a1, a2, ... make surface k the hit with probability
//          a_k (1 - a_1) ... (1 - a_{k-1}) and leave the ray unoccluded with
//          probability (1 - a_1) (1 - a_2) ...: the weights of Porter and
//          Duff's "over", which section 3.9.4 asks BLEND to compute. So the
//          expected radiance of a path is that of the composited surfaces and
//          the expected visibility of a shadow ray their transmittance:
//          unbiased, as long as the decisions are independent of each other
//          and of the path's other random numbers.
//
// The decision's random number is a hash of the path (pixel, sample index,
// seed), the ray's number in the path and the candidate triangle
// (alphaUniform), not a number drawn in traversal order: it does not depend
// on the order in which the tree presents candidates (closest-hit traversal
// may test a farther triangle first), on the kernel form or on the device, so
// the CPU reference, the megakernel and the wavefront stages decide alike and
// the traversal returns the nearest accepted candidate. Rays are numbered in
// the order of shared/integrator.h's loop: at bounce b the closest-hit ray,
// then its lightSamples shadow rays. Every ray decides afresh: a shadow ray
// and the BSDF ray that may later cross the same triangle draw different
// numbers. Each ray's estimate is unbiased on its own (MIS weights depend on
// densities, not on visibility), so nothing needs them to agree, and
// independent decisions make the two estimates less correlated than shared
// ones would. A ray meets a triangle at most once (a plane cuts a line once),
// so one number per (ray, triangle) is all it needs. The numbers come from the
// independent sampler's hash (shared/rng.h, pcg4d) at dimensions 2^31 and up,
// which no path reaches, so they are independent of the path's own numbers
// whatever the sampler.
#ifndef VKPATH_SHARED_ALPHA_H
#define VKPATH_SHARED_ALPHA_H

#include "shared/compat.h"
#include "shared/records.h"
#include "shared/rng.h"

// MaterialAlpha::mode; the same numbers as scene::AlphaMode.
#define VKP_ALPHA_OPAQUE 0u
#define VKP_ALPHA_MASK 1u
#define VKP_ALPHA_BLEND 2u

// The first random dimension of the alpha decisions: ray r of a path draws
// its key at VKP_DIM_ALPHA + r of the independent sampler.
#define VKP_DIM_ALPHA 0x80000000u

VKP_NAMESPACE_BEGIN

// What the traversal reads of a material to test a candidate hit: one record
// per scene material, uploaded only for scenes with a MASK or BLEND triangle
// (SceneInfo::alphaTested).
// MaterialAlpha's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_MATERIAL_ALPHA_FIELDS(F)                                                         \
    /* VKP_ALPHA_* */                                                                        \
    F(uint, mode, 0)                                                                         \
    /* MASK: alpha below this is a hole (glTF alphaCutoff) */                                \
    F(float, cutoff, 1)                                                                      \
    /* baseColorFactor's alpha */                                                            \
    F(float, alpha, 2)                                                                       \
    /* the material's VKP_SLOT_BASE_COLOR TextureSlot (shared/texture.h), whose texture's */ \
    /* alpha multiplies; VKP_NO_TEXTURE when it has none */                                  \
    F(uint, baseColorSlot, 3)
struct MaterialAlpha {
    VKP_MATERIAL_ALPHA_FIELDS(VKP_FIELD_DECLARE)
};

// The number of the closest-hit ray of bounce `bounce`, and of the shadow ray
// of its light sample `index` (of lightSamples), among the rays of one path.
VKP_FN uint alphaClosestRay(uint bounce, uint lightSamples) {
    return bounce * (lightSamples + 1u);
}
VKP_FN uint alphaShadowRay(uint bounce, uint lightSamples, uint index) {
    return bounce * (lightSamples + 1u) + 1u + index;
}

// The key of ray `ray` of the path of `key` (any sampler): one word that
// alphaUniform hashes with each candidate.
VKP_FN uint alphaRayKey(RngKey key, uint ray) {
    return rngBits(makeRngKey(key.pixel, key.sampleIndex, key.seed), VKP_DIM_ALPHA + ray);
}

// The uniform number in [0, 1) that decides whether triangle `triangle`
// (BvhPrimitive::id) is there for the ray of key `rayKey`.
VKP_FN float alphaUniform(uint rayKey, uint triangle) {
    return uintToUnitFloat(pcg4d(uvec4(rayKey, triangle, VKP_DIM_ALPHA, 0u)).x);
}

// Whether the ray of key `rayKey` meets triangle `triangle`, of material
// `material`, at a point whose alpha is `alpha`. BLEND: u < alpha with u a
// multiple of 2^-24 in [0, 1), so alpha 0 never and alpha 1 always covers,
// and the probability is alpha rounded up to a multiple of 2^-24.
VKP_FN bool alphaCovers(MaterialAlpha material, float alpha, uint rayKey, uint triangle) {
    if (material.mode == VKP_ALPHA_MASK) return alpha >= material.cutoff;
    return alphaUniform(rayKey, triangle) < alpha;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD MaterialAlpha
VKP_RECORD_CHECK(VKP_MATERIAL_ALPHA_FIELDS, 1)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_ALPHA_H
