// The random number generator: stateless and counter-based, so any sample of
// any pixel can be regenerated anywhere (CPU or GPU, any wave, any order) from
// its coordinates alone, and both sides produce the same bits.
//
// u(pixel, sampleIndex, dimension) hashes the four 32-bit counters
// (pixel, sampleIndex, dimension, seed) with pcg4d, the 4-D PCG-style hash of
// Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020,
// which passes TestU01's BigCrush on its output.
//
// Two samplers draw from the same counters (RngKey::samplerKind):
//  - independent: every (pixel, sample, dimension) hashed on its own;
//  - sobol: dimensions taken in pairs (2d, 2d + 1), each pair an
//    Owen-scrambled 2-D Sobol' sequence over the pixel's sample indices
//    (shared/sobol.h), shuffled and scrambled by a hash of (pixel, pair,
//    seed). The first 2^k samples of a pixel then form a (0,k,2)-net in
//    every pair (one point in each elementary interval of area 2^-k), and
//    different pairs and pixels are decorrelated by their own shuffles, as
//    in pbrt-v4's padded Sobol' sampler. Callers draw 2-D quantities from a
//    pair starting at an even dimension (path_tracer.h pads its layout so)
//    to get that stratification.
#ifndef VKPATH_SHARED_RNG_H
#define VKPATH_SHARED_RNG_H

#include "shared/compat.h"
#include "shared/features.h"
#include "shared/sobol.h"

// RngKey::samplerKind and SceneInfo::samplerKind (wavefront::SamplerKind on the host).
#define VKP_SAMPLER_INDEPENDENT 0u
#define VKP_SAMPLER_SOBOL 1u

VKP_NAMESPACE_BEGIN

VKP_FN uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + uvec4(1013904223u);
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

// The top 24 bits as a float in [0, 1): every value is exact, and the largest
// is 1 - 2^-24, so u < 1 holds after any float arithmetic that keeps it exact.
VKP_FN float uintToUnitFloat(uint bits) {
    return float(bits >> 8u) * 5.9604644775390625e-08f;  // 2^-24
}

// Where a random number comes from: pixel index (y * width + x), sample index
// within the pixel, the render's seed and the sampler. `dimension` counts the
// numbers one path consumes, in a fixed order (see the dimension constants of
// each stage).
struct RngKey {
    uint pixel;
    uint sampleIndex;
    uint seed;
    uint samplerKind;  // VKP_SAMPLER_* (GLSL reserves `sampler`)
};

VKP_FN RngKey makeRngKey(uint pixel, uint sampleIndex, uint seed, uint samplerKind) {
    RngKey key;
    key.pixel = pixel;
    key.sampleIndex = sampleIndex;
    key.seed = seed;
    key.samplerKind = samplerKind;
    return key;
}

// The sampler a kernel uses for `samplerKind` (SceneInfo::samplerKind): a
// constant when it meets only one (shared/features.h), so the other's code
// is compiled out of every rngBits below.
VKP_FN uint featureSampler(uint samplerKind) {
    if (!hasFeature(VKP_FEATURE_SAMPLER_SOBOL)) return VKP_SAMPLER_INDEPENDENT;
    if (!hasFeature(VKP_FEATURE_SAMPLER_INDEPENDENT)) return VKP_SAMPLER_SOBOL;
    return samplerKind;
}

// The independent sampler's key, for code that needs no stratification.
VKP_FN RngKey makeRngKey(uint pixel, uint sampleIndex, uint seed) {
    return makeRngKey(pixel, sampleIndex, seed, VKP_SAMPLER_INDEPENDENT);
}

VKP_FN uint rngBits(RngKey key, uint dimension) {
    if (key.samplerKind == VKP_SAMPLER_SOBOL) {
        // One hash per (pixel, pair, seed) seeds the pair's index shuffle
        // and its two coordinates' scrambles.
        uvec4 h = pcg4d(uvec4(key.pixel, dimension >> 1u, key.seed, 0u));
        uint component = dimension & 1u;
        return scrambledSobol2(key.sampleIndex, component, h.x, component == 0u ? h.y : h.z);
    }
    return pcg4d(uvec4(key.pixel, key.sampleIndex, dimension, key.seed)).x;
}

VKP_FN float rngUniform(RngKey key, uint dimension) {
    return uintToUnitFloat(rngBits(key, dimension));
}

// Dimensions `dimension` and `dimension` + 1: the bits of two rngBits calls.
// With the Sobol' sampler an even `dimension` starts a pair, whose two
// coordinates share one hash and one index shuffle: half the work of two
// calls (the CPU reference spent a quarter of its time in the Sobol' sampler).
VKP_FN uvec2 rngBits2(RngKey key, uint dimension) {
    if (key.samplerKind == VKP_SAMPLER_SOBOL && (dimension & 1u) == 0u) {
        uvec4 h = pcg4d(uvec4(key.pixel, dimension >> 1u, key.seed, 0u));
        return scrambledSobol2Point(key.sampleIndex, h.x, h.y, h.z);
    }
    return uvec2(rngBits(key, dimension), rngBits(key, dimension + 1u));
}

VKP_FN vec2 rngUniform2(RngKey key, uint dimension) {
    uvec2 bits = rngBits2(key, dimension);
    return vec2(uintToUnitFloat(bits.x), uintToUnitFloat(bits.y));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_RNG_H
