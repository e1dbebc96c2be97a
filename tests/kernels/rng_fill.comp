// Test kernel: writes rngBits(key, dimension) of either sampler for a grid of
// counters, so the RNG and sampler tests can compare GPU bits with the same
// function on the CPU. Dimensions 4k and 4k + 1 come from rngBits, 4k + 2 and
// 4k + 3 from the two halves of rngBits2(key, 4k + 2), which must give the
// same bits.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "shared/rng.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) writeonly buffer Bits { uint bits[]; };
layout(push_constant, scalar) uniform Push {
    uint count;       // values to write
    uint pixels;      // counter layout: i = (sample * dims + dimension) * pixels + pixel
    uint dimensions;
    uint seed;
    uint samplerKind;  // VKP_SAMPLER_*
    uint firstSample;  // sample indices start here (wrapping at 2^32)
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    uint pixel = i % pixels;
    uint dimension = (i / pixels) % dimensions;
    uint sampleIndex = firstSample + i / (pixels * dimensions);
    RngKey key = makeRngKey(pixel, sampleIndex, seed, samplerKind);
    uint pairStart = dimension & ~1u;
    if ((dimension & 2u) == 0u)
        bits[i] = rngBits(key, dimension);
    else
        bits[i] = (dimension & 1u) == 0u ? rngBits2(key, pairStart).x : rngBits2(key, pairStart).y;
}
