// The Sobol' sampler (shared/sobol.h through rngBits with VKP_SAMPLER_SOBOL):
// the GPU produces the CPU's bits, every dimension and pair is uniform (the
// independent sampler's chi-square tests), and what it is for: the 2^k
// samples of any aligned block of a pixel's sample indices form a
// (0,k,2)-net in every pair of dimensions, which independent samples do not.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/rng_fill.h"
#include "shared/rng.h"
#include "support/statistics.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;

using test::RngFillPush;

// 500 pixels x 20 dimensions (10 pairs) x 16 samples: 1.6 x 10^5 values.
struct Grid {
    uint32_t pixels = 500, dimensions = 20, samples = 16;
    uint32_t seed = 0, firstSample = 0;
    uint32_t count() const { return pixels * dimensions * samples; }
    // rng_fill.comp's layout: i = (sample * dimensions + dimension) * pixels + pixel.
    uint32_t index(uint32_t pixel, uint32_t sample, uint32_t dimension) const {
        return (sample * dimensions + dimension) * pixels + pixel;
    }
};

std::vector<uint32_t> gpuBits(const Grid& g) {
    vk::Context& context = test::context();
    vk::Buffer bits(context, g.count() * sizeof(uint32_t));
    vk::Kernel kernel(context, "rng_fill");
    kernel.dispatch(
        g.count(), {{0, &bits}},
        RngFillPush{g.count(), g.pixels, g.dimensions, g.seed, VKP_SAMPLER_SOBOL, g.firstSample});
    return bits.download<uint32_t>();
}

uint32_t sobolBits(uint32_t pixel, uint32_t sample, uint32_t dimension, uint32_t seed) {
    return shared::rngBits(shared::makeRngKey(pixel, sample, seed, VKP_SAMPLER_SOBOL), dimension);
}

// Bit for bit, at small sample indices and at the last ones below 2^32.
TEST(SobolSampler, GpuMatchesCpuBitForBit) {
    Grid small;
    Grid last;
    last.seed = 0xdeadbeefu;
    last.firstSample = 0u - last.samples;
    for (const Grid& g : {small, last}) {
        const auto gpu = gpuBits(g);
        ASSERT_EQ(gpu.size(), g.count());
        uint32_t mismatches = 0, first = g.count();
        for (uint32_t s = 0; s < g.samples; ++s)
            for (uint32_t d = 0; d < g.dimensions; ++d)
                for (uint32_t p = 0; p < g.pixels; ++p) {
                    const uint32_t i = g.index(p, s, d);
                    if (gpu[i] != sobolBits(p, g.firstSample + s, d, g.seed)) {
                        if (first == g.count()) first = i;
                        ++mismatches;
                    }
                }
        EXPECT_EQ(mismatches, 0u) << "first sample " << g.firstSample << ", first mismatch at "
                                  << first;
    }
}

// rngBits2 gives the bits of two rngBits calls, for either sampler and a
// pair starting at an even dimension (the Sobol' pair computed together) or
// an odd one (two pairs). The GPU's rngBits2 is checked by the test above:
// rng_fill.comp writes half of its dimensions through it.
TEST(SobolSampler, PairsOfNumbersAreTwoSingleNumbers) {
    for (const uint32_t sampler : {VKP_SAMPLER_INDEPENDENT, VKP_SAMPLER_SOBOL})
        for (uint32_t pixel = 0; pixel < 64; ++pixel)
            for (const uint32_t sample : {0u, 1u, 7u, 1000u, 0xffffffffu})
                for (uint32_t d = 0; d < 42; ++d) {
                    const shared::RngKey key =
                        shared::makeRngKey(pixel * 7919u, sample, 12345u, sampler);
                    const glm::uvec2 pair = shared::rngBits2(key, d);
                    ASSERT_EQ(pair.x, shared::rngBits(key, d))
                        << sampler << " " << pixel << " " << sample << " " << d;
                    ASSERT_EQ(pair.y, shared::rngBits(key, d + 1u))
                        << sampler << " " << pixel << " " << sample << " " << d;
                }
}

// Each uniformity test at 1% significance, Sidak-corrected over all of them:
// 20 single dimensions, within-pair and across-pair 2-D tests, first samples.
// shared/sobol.h's scrambledSobol2 as its comment writes it out: dimension
// 1 as the xor of the direction numbers v_1 = 2^31, v_k = v_{k-1} xor
// (v_{k-1} >> 1) over the set bits of the index, and every bit reversal
// done. The shader's version computes dimension 1 in closed form and drops
// the reversals that cancel; the two must agree on every bit.
uint32_t sobolDimension1ByDirectionNumbers(uint32_t index) {
    uint32_t result = 0u;
    for (uint32_t v = 0x80000000u; index != 0u; index >>= 1u, v ^= v >> 1u)
        if ((index & 1u) != 0u) result ^= v;
    return result;
}

uint32_t scrambledSobol2AsDefined(uint32_t index, uint32_t component, uint32_t shuffleSeed,
                                  uint32_t scrambleSeed) {
    const uint32_t shuffled = shared::nestedUniformScramble(index, shuffleSeed);
    const uint32_t bits = component == 0u ? glm::bitfieldReverse(shuffled)
                                          : sobolDimension1ByDirectionNumbers(shuffled);
    return shared::nestedUniformScramble(bits, scrambleSeed);
}

TEST(SobolSampler, ClosedFormMatchesTheDirectionNumbers) {
    // Every single-bit index (each direction number alone), then hashed
    // indices and seeds.
    for (uint32_t bit = 0; bit < 32; ++bit)
        EXPECT_EQ(glm::bitfieldReverse(shared::reversedSobolDimension1(1u << bit)),
                  sobolDimension1ByDirectionNumbers(1u << bit))
            << "bit " << bit;
    uint32_t mismatches = 0;
    for (uint32_t i = 0; i < 200000u; ++i) {
        const glm::uvec4 h = shared::pcg4d(glm::uvec4(i, 7u, 11u, 13u));
        const uint32_t index = i < 1000u ? i : h.x;
        for (uint32_t component = 0; component < 2u; ++component)
            if (shared::scrambledSobol2(index, component, h.y, h.z) !=
                scrambledSobol2AsDefined(index, component, h.y, h.z))
                ++mismatches;
    }
    EXPECT_EQ(mismatches, 0u);
}

// shared::bitfieldReverse, GFNI's on x86 machines that have it
// (shared/compat.h), against GLM's: every single bit, then hashed words.
TEST(SobolSampler, BitReversalIsGlms) {
    for (uint32_t bit = 0; bit < 32; ++bit)
        EXPECT_EQ(shared::bitfieldReverse(1u << bit), 1u << (31u - bit));
    uint32_t mismatches = 0;
    for (uint32_t i = 0; i < 1000000u; ++i) {
        const uint32_t word = shared::pcg4d(glm::uvec4(i, 3u, 5u, 7u)).x;
        if (shared::bitfieldReverse(word) != glm::bitfieldReverse(word)) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0u);
}

constexpr int UNIFORMITY_TESTS = 20 + 2 + 1;
const double ALPHA = test::sidakAlpha(0.01, UNIFORMITY_TESTS);

// 100 samples per pixel, not a power of two: the last 36 are part of a
// block of 64, so the counts are not exact by construction.
Grid uniformityGrid() {
    Grid g;
    g.pixels = 1000;
    g.samples = 100;
    g.seed = 7;
    return g;
}

TEST(SobolSampler, EachDimensionUniformIn64Bins) {
    const Grid g = uniformityGrid();
    const auto bits = gpuBits(g);
    for (uint32_t d = 0; d < g.dimensions; ++d) {
        std::vector<double> observed(64, 0), expected(64, double(g.pixels) * g.samples / 64);
        for (uint32_t s = 0; s < g.samples; ++s)
            for (uint32_t p = 0; p < g.pixels; ++p)
                observed[static_cast<size_t>(shared::uintToUnitFloat(bits[g.index(p, s, d)]) *
                                             64)] += 1;
        const auto result = test::chiSquareTest(observed, expected);
        EXPECT_GT(result.pValue, ALPHA) << "dimension " << d << ": chi2 " << result.statistic;
    }
}

// Pairs (2j, 2j + 1) are one scrambled Sobol' sequence; pairs (2j + 1, 2j + 2)
// straddle two sequences, which their own shuffles must make independent.
// 32x32 cells each.
TEST(SobolSampler, PairsOfDimensionsUniformIn2D) {
    const Grid g = uniformityGrid();
    const auto bits = gpuBits(g);
    for (uint32_t offset : {0u, 1u}) {
        constexpr int N = 32;
        std::vector<double> observed(N * N, 0);
        double pairs = 0;
        for (uint32_t s = 0; s < g.samples; ++s)
            for (uint32_t d = offset; d + 1 < g.dimensions; d += 2)
                for (uint32_t p = 0; p < g.pixels; ++p) {
                    const float u = shared::uintToUnitFloat(bits[g.index(p, s, d)]);
                    const float v = shared::uintToUnitFloat(bits[g.index(p, s, d + 1)]);
                    observed[static_cast<size_t>(u * N) * N + static_cast<size_t>(v * N)] += 1;
                    pairs += 1;
                }
        std::vector<double> expected(N * N, pairs / (N * N));
        const auto result = test::chiSquareTest(observed, expected);
        EXPECT_GT(result.pValue, ALPHA)
            << "pairs from dimension " << offset << ": chi2 " << result.statistic;
    }
}

// The scramble randomises every point: sample 0 of an unscrambled Sobol'
// sequence is 0 in every dimension, here it is uniform over pixels.
TEST(SobolSampler, FirstSampleUniformOverPixels) {
    const Grid g = uniformityGrid();
    const auto bits = gpuBits(g);
    std::vector<double> observed(64, 0), expected(64, double(g.pixels) * g.dimensions / 64);
    for (uint32_t d = 0; d < g.dimensions; ++d)
        for (uint32_t p = 0; p < g.pixels; ++p)
            observed[static_cast<size_t>(shared::uintToUnitFloat(bits[g.index(p, 0, d)]) * 64)] +=
                1;
    const auto result = test::chiSquareTest(observed, expected);
    EXPECT_GT(result.pValue, ALPHA) << "chi2 " << result.statistic;
}

// Whether samples [first, first + 2^k) of `pixel` in dimensions (d, d + 1),
// as the floats paths use, put exactly one point in each elementary interval
// [a 2^-i, (a+1) 2^-i) x [b 2^-(k-i), (b+1) 2^-(k-i)), for every i in 0..k.
// Also checks that every value is in [0, 1).
bool isNet(uint32_t sampler, uint32_t pixel, uint32_t d, uint32_t seed, uint32_t first,
           uint32_t k) {
    const uint32_t n = 1u << k;
    std::vector<float> u(n), v(n);
    for (uint32_t s = 0; s < n; ++s) {
        const auto key = shared::makeRngKey(pixel, first + s, seed, sampler);
        const glm::vec2 uv = shared::rngUniform2(key, d);
        EXPECT_TRUE(uv.x >= 0.0f && uv.x < 1.0f && uv.y >= 0.0f && uv.y < 1.0f)
            << uv.x << ", " << uv.y;
        u[s] = uv.x;
        v[s] = uv.y;
    }
    for (uint32_t i = 0; i <= k; ++i) {
        const float columns = std::ldexp(1.0f, int(i)), rows = std::ldexp(1.0f, int(k - i));
        std::vector<bool> occupied(n, false);
        for (uint32_t s = 0; s < n; ++s) {
            const uint32_t cell = uint32_t(u[s] * columns) * uint32_t(rows) + uint32_t(v[s] * rows);
            if (occupied[cell]) return false;
            occupied[cell] = true;
        }
    }
    return true;
}

// Blocks of 2^k samples for k = 0..12: the first of the pixel, the fourth,
// and the last one below 2^32; in pairs at 0 (pixel jitter) and deep in the
// path (the pairs a bounce draws), for several pixels and seeds.
TEST(SobolSampler, AlignedBlocksAreNetsInEveryPair) {
    for (uint32_t seed : {0u, 12345u})
        for (uint32_t pixel : {0u, 1u, 777u})
            for (uint32_t d : {0u, 2u, 6u, 40u})
                for (uint32_t k = 0; k <= 12; ++k)
                    for (uint32_t first : {0u, 3u << k, 0u - (1u << k)}) {
                        EXPECT_TRUE(isNet(VKP_SAMPLER_SOBOL, pixel, d, seed, first, k))
                            << "seed " << seed << " pixel " << pixel << " dimension " << d
                            << " samples " << first << " + 2^" << k;
                    }
}

// The property has power: independent samples break it (for 16 points the
// chance that 16 uniform points form a (0,4,2)-net is below 10^-5).
TEST(SobolSampler, IndependentSamplesAreNoNet) {
    for (uint32_t pixel : {0u, 1u, 777u})
        for (uint32_t d : {0u, 2u, 6u})
            EXPECT_FALSE(isNet(VKP_SAMPLER_INDEPENDENT, pixel, d, 0u, 0u, 4));
}

}  // namespace
