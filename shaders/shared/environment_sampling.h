// Importance sampling of the environment map in proportion to
// luminance x sin(theta), texel by texel, through an alias table over the
// texels (shared/alias.h explains why not a float marginal/conditional CDF:
// with a 10^7 sun, whole rows of sky fall below one float ulp of the CDF).
//
// Sampling uses 4 random dimensions: two 32-bit words for the alias table,
// then a point inside the chosen texel:
//   bucket = aliasBucket(bits0, texels); texel = aliasResolve(table[bucket], bucket, bits1);
//   s = envSampleInTexel(info, texel, jitter);
//   pdf = envDirectionPdf(info, table[s.pdfTexel].probability, s.direction);
#ifndef VKPATH_SHARED_ENVIRONMENT_SAMPLING_H
#define VKPATH_SHARED_ENVIRONMENT_SAMPLING_H

#include "shared/compat.h"
#include "shared/alias.h"
#include "shared/constants.h"
#include "shared/environment_map.h"

VKP_NAMESPACE_BEGIN

struct EnvironmentInfo {
    uint width;         // map size in texels
    uint height;
    float strength;     // radiance multiplier
    float cosRotation;  // rotation about +Y applied to the map (world = R * map)
    float sinRotation;
    vec3 color;         // constant radiance when there is no map (width = 0)
};

// Map direction of a world direction (undoing the rotation), and back.
VKP_FN vec3 envWorldToMap(EnvironmentInfo info, vec3 d) {
    return vec3(info.cosRotation * d.x - info.sinRotation * d.z, d.y,
                info.sinRotation * d.x + info.cosRotation * d.z);
}

VKP_FN vec3 envMapToWorld(EnvironmentInfo info, vec3 d) {
    return vec3(info.cosRotation * d.x + info.sinRotation * d.z, d.y,
                -info.sinRotation * d.x + info.cosRotation * d.z);
}

VKP_FN uint envTexelOfUv(EnvironmentInfo info, vec2 uv) {
    uint x = min(uint(uv.x * float(info.width)), info.width - 1u);
    uint y = min(uint(uv.y * float(info.height)), info.height - 1u);
    return y * info.width + x;
}

// Solid-angle density of a map direction inside a texel of discrete
// probability `probability`: the texel is sampled uniformly in (u, v), and
// d omega = 2 pi^2 sin(theta) du dv. sin(theta) comes from the direction
// itself (length of its xz part), not from v through sin(), so that every
// path to the pdf of one direction computes the same number.
VKP_FN float envPdf(EnvironmentInfo info, float probability, vec3 mapDirection) {
    float sinTheta = length(vec2(mapDirection.x, mapDirection.z));
    if (!(sinTheta > 0.0f) || !(probability > 0.0f)) return 0.0f;
    float texelsPerUnitUv = float(info.width) * float(info.height);
    return probability * texelsPerUnitUv / (2.0f * VKP_PI * VKP_PI * sinTheta);
}

struct EnvSample {
    vec3 direction;  // world space
    vec2 uv;         // map coordinates
    uint pdfTexel;   // the texel whose probability gives the pdf: read it, then call envDirectionPdf
};

// A point uniformly inside the chosen texel. Its pdf is evaluated from the
// direction (envDirectionPdf with the probability of s.pdfTexel), exactly as for
// a BSDF-sampled direction that escapes: the two MIS strategies then agree
// to the bit. The texel looked up from the direction is the chosen one except
// within ~1e-7 of a texel edge, where rounding of the mapping may pick the
// neighbour (measured by the tests).
VKP_FN EnvSample envSampleInTexel(EnvironmentInfo info, uint texel, vec2 jitter) {
    uint x = texel % info.width;
    uint y = texel / info.width;
    EnvSample s;
    s.uv = vec2((float(x) + jitter.x) / float(info.width), (float(y) + jitter.y) / float(info.height));
    // Keep the point inside the map: a jitter of 1 - 2^-24 can round up to
    // the texel's far edge, which for the last column or row is 1. (There the
    // point may fall in the neighbouring texel, which pdfTexel then names.)
    s.uv = min(s.uv, vec2(VKP_ONE_MINUS_EPSILON));
    vec3 mapDirection = equirectDirection(s.uv.x, s.uv.y);
    s.direction = envMapToWorld(info, mapDirection);
    s.pdfTexel = envTexelOfUv(info, equirectUv(mapDirection));
    return s;
}

// The pdf of a world direction, given the probability of its texel
// (the texel is envTexelOfUv(info, equirectUv(envWorldToMap(info, d)))).
VKP_FN float envDirectionPdf(EnvironmentInfo info, float texelProbability, vec3 worldDirection) {
    return envPdf(info, texelProbability, envWorldToMap(info, worldDirection));
}

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::EnvironmentInfo) == 32);
#endif

#endif  // VKPATH_SHARED_ENVIRONMENT_SAMPLING_H
