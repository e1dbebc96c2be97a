// Push constants of tests/kernels/rng_fill.comp (scalar layout: six uint32).
#pragma once

#include <cstdint>

namespace vkpath::test {

struct RngFillPush {
    uint32_t count;   // values to write
    uint32_t pixels;  // counter layout: i = (sample * dimensions + dimension) * pixels + pixel
    uint32_t dimensions;
    uint32_t seed;
    uint32_t sampler;      // VKP_SAMPLER_*
    uint32_t firstSample;  // sample indices start here (wrapping at 2^32)
};

}  // namespace vkpath::test
