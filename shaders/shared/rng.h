// The random number generator: stateless and counter-based, so any sample of
// any pixel can be regenerated anywhere (CPU or GPU, any wave, any order) from
// its coordinates alone, and both sides produce the same bits.
//
// u(pixel, sampleIndex, dimension) hashes the four 32-bit counters
// (pixel, sampleIndex, dimension, seed) with pcg4d, the 4-D PCG-style hash of
// Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020,
// which passes TestU01's BigCrush on its output.
#ifndef VKPATH_SHARED_RNG_H
#define VKPATH_SHARED_RNG_H

#include "shared/compat.h"

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
// within the pixel, and the render's seed. `dimension` counts the numbers one
// path consumes, in a fixed order (see the dimension constants of each stage).
struct RngKey {
    uint pixel;
    uint sampleIndex;
    uint seed;
};

VKP_FN RngKey makeRngKey(uint pixel, uint sampleIndex, uint seed) {
    RngKey key;
    key.pixel = pixel;
    key.sampleIndex = sampleIndex;
    key.seed = seed;
    return key;
}

VKP_FN uint rngBits(RngKey key, uint dimension) {
    return pcg4d(uvec4(key.pixel, key.sampleIndex, dimension, key.seed)).x;
}

VKP_FN float rngUniform(RngKey key, uint dimension) {
    return uintToUnitFloat(rngBits(key, dimension));
}

VKP_FN vec2 rngUniform2(RngKey key, uint dimension) {
    return vec2(rngUniform(key, dimension), rngUniform(key, dimension + 1u));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_RNG_H
