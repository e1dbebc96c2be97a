// Homogeneous participating media: the record the kernels read
// (SceneTables::media) and the two things a path does in one, cross a
// segment of it and scatter in it (docs/SCENES.md, "Media").
#ifndef VKPATH_SHARED_MEDIUM_H
#define VKPATH_SHARED_MEDIUM_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/records.h"

// The media array: entry 0 is the fog around everything (render --fog-*;
// all zero without one), entry 1 + m the inside of material m (a
// transmitting material's KHR_materials_volume and volume_scatter; all
// zero for others).
#define VKP_FOG_MEDIUM 0u

VKP_NAMESPACE_BEGIN

// Medium's fields (type, name, first 32-bit word; shared/records.h):
// coefficients per metre (world units).
#define VKP_MEDIUM_FIELDS(F)                               \
    /* sigma_s */                                          \
    F(vec3, scattering, 0)                                 \
    /* Henyey-Greenstein g (shared/phase.h), in (-1, 1) */ \
    F(float, anisotropy, 3)                                \
    /* sigma_a */                                          \
    F(vec3, absorption, 4)                                 \
    /* 0: whole texels */                                  \
    F(uint, padding, 7)
struct Medium {
    VKP_MEDIUM_FIELDS(VKP_FIELD_DECLARE)
};

// The grid medium's record (SceneTables::gridMedium; render --volume): a
// dense grid of densities (SceneTables::gridDensity, x fastest), voxel
// (i, j, k) centred at origin + (i, j, k) / inverseVoxelSize in world space,
// trilinear between centres and 0 outside them, and its majorants
// (SceneTables::gridMajorant): per cell of majorantCell^3 voxels, the largest
// density the trilinear interpolation takes in it. sigma_t = densityScale x
// density, sigma_s = albedo x sigma_t.
#define VKP_GRID_MEDIUM_FIELDS(F)                  \
    F(vec3, origin, 0)                             \
    F(float, densityScale, 3)                      \
    F(vec3, inverseVoxelSize, 4)                   \
    F(float, anisotropy, 7)                        \
    F(uvec3, resolution, 8)                        \
    /* voxels per majorant cell along each axis */ \
    F(uint, majorantCell, 11)                      \
    F(uvec3, majorantResolution, 12)               \
    F(uint, padding, 15)                           \
    F(vec3, albedo, 16)                            \
    F(float, padding2, 19)
struct GridMedium {
    VKP_GRID_MEDIUM_FIELDS(VKP_FIELD_DECLARE)
};

// exp(-sigma t) per channel, 1 where sigma is 0 (also for t = VKP_FLT_MAX:
// 0 * FLT_MAX is 0, never the NaN of 0 * infinity).
VKP_FN vec3 mediumDecay(vec3 sigma, float t) {
    return exp(-sigma * t);
}

// What is left of light that crossed distance t of `m`: exp(-(sigma_a +
// sigma_s) t).
VKP_FN vec3 mediumTransmittanceAlong(VKP_IN(Medium) m, float t) {
    return mediumDecay(m.absorption + m.scattering, t);
}

// The medium along a segment of length tEnd (VKP_FLT_MAX: a ray that leaves
// the scene): where the path scatters in it, if it does, and the weight
// that keeps the estimate unbiased.
struct FreeFlight {
    bool scattered;  // true: at distance t < tEnd; false: the path reaches tEnd
    float t;
    vec3 weight;  // by which the path's throughput is multiplied
};

// The distance to the next scattering event is drawn from the scattering
// coefficient alone (one channel, chosen uniformly by u.y: spectral MIS with
// the balance heuristic over the three channels, the one-sample estimator
// of pbrt-v3's HomogeneousMedium::Sample), and absorption stays a
// deterministic weight exp(-sigma_a t): a medium that only absorbs never
// scatters and gives Beer-Lambert exactly, and one that scatters little
// spends no events on absorption. With p_c(t) = sigma_s,c exp(-sigma_s,c t):
//
//   scattered at t < tEnd:  weight = sigma_s exp(-sigma_t t) / mean_c p_c(t)
//   reached tEnd:           weight = exp(-sigma_t tEnd) / mean_c exp(-sigma_s,c tEnd)
//
// (sigma_t = sigma_a + sigma_s), each channel's expectation the radiative
// transfer equation's (pbrt-v4, section 14.1, with sigma_s in place of the
// majorant and sigma_a as an exact weight).
// The weight of a path that crossed distance t of `m` without scattering,
// as sampleFreeFlight draws it: exp(-sigma_t t) over the probability of no
// event before t.
VKP_FN vec3 freeFlightPassWeight(VKP_IN(Medium) m, float t) {
    vec3 scatteringDecay = mediumDecay(m.scattering, t);
    float probability = (scatteringDecay.x + scatteringDecay.y + scatteringDecay.z) / 3.0f;
    return scatteringDecay * mediumDecay(m.absorption, t) / probability;
}

VKP_FN FreeFlight sampleFreeFlight(VKP_IN(Medium) m, float tEnd, vec2 u) {
    FreeFlight flight;
    flight.scattered = false;
    flight.t = tEnd;
    uint channel = min(uint(u.y * 3.0f), 2u);
    float sigma = m.scattering[channel];
    if (sigma > 0.0f) {
        float t = -log(1.0f - u.x) / sigma;
        if (t < tEnd) {
            flight.scattered = true;
            flight.t = t;
        }
    }
    if (flight.scattered) {
        vec3 density = m.scattering * mediumDecay(m.scattering, flight.t);
        float pdf = (density.x + density.y + density.z) / 3.0f;
        flight.weight =
            pdf > 0.0f ? density * mediumDecay(m.absorption, flight.t) / pdf : vec3(0.0f);
    } else {
        flight.weight = freeFlightPassWeight(m, flight.t);
    }
    return flight;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD Medium
VKP_RECORD_CHECK(VKP_MEDIUM_FIELDS, 2)
#undef VKP_RECORD
#define VKP_RECORD GridMedium
VKP_RECORD_CHECK(VKP_GRID_MEDIUM_FIELDS, 5)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_MEDIUM_H
