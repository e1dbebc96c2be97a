// The counter-based RNG: the GPU produces the same bits as the CPU for 10^6
// counters, and its floats are uniform in 1-D and in 2-D pairs.
#include "shared/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/rng_fill.h"
#include "support/statistics.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;

using test::RngFillPush;

constexpr uint32_t PIXELS = 1000, DIMENSIONS = 10, SAMPLES = 100;  // 10^6 values
constexpr uint32_t COUNT = PIXELS * DIMENSIONS * SAMPLES;

std::vector<uint32_t> gpuBits(uint32_t seed) {
    vk::Context& context = test::context();
    vk::Buffer bits(context, COUNT * sizeof(uint32_t));
    vk::Kernel kernel(context, "rng_fill");
    kernel.dispatch(COUNT, {{0, &bits}},
                    RngFillPush{COUNT, PIXELS, DIMENSIONS, seed, VKP_SAMPLER_INDEPENDENT, 0});
    return bits.download<uint32_t>();
}

uint32_t cpuBits(uint32_t i, uint32_t seed) {
    const uint32_t pixel = i % PIXELS, dimension = (i / PIXELS) % DIMENSIONS,
                   sample = i / (PIXELS * DIMENSIONS);
    return shared::rngBits(shared::makeRngKey(pixel, sample, seed), dimension);
}

TEST(Rng, GpuMatchesCpuBitForBit) {
    for (uint32_t seed : {0u, 0xdeadbeefu}) {
        const auto gpu = gpuBits(seed);
        ASSERT_EQ(gpu.size(), COUNT);
        uint32_t mismatches = 0, first = COUNT;
        for (uint32_t i = 0; i < COUNT; ++i)
            if (gpu[i] != cpuBits(i, seed)) {
                if (first == COUNT) first = i;
                ++mismatches;
            }
        EXPECT_EQ(mismatches, 0u) << "seed " << seed << ", first at " << first;
    }
}

TEST(Rng, FloatsStayBelowOne) {
    EXPECT_EQ(shared::uintToUnitFloat(0xffffffffu), 1.0f - std::ldexp(1.0f, -24));
    EXPECT_EQ(shared::uintToUnitFloat(0u), 0.0f);
}

// 1% significance for each of the two tests, Sidak-corrected over both.
const double ALPHA = test::sidakAlpha(0.01, 2);

TEST(Rng, UniformIn64Bins) {
    const auto bits = gpuBits(7);
    std::vector<double> observed(64, 0), expected(64, double(COUNT) / 64);
    for (uint32_t b : bits) observed[static_cast<size_t>(shared::uintToUnitFloat(b) * 64)] += 1;
    const auto result = test::chiSquareTest(observed, expected);
    EXPECT_GT(result.pValue, ALPHA)
        << "chi2 " << result.statistic << " dof " << result.degreesOfFreedom;
}

TEST(Rng, PairsOfDimensionsUniformIn2D) {
    // Consecutive dimensions of one sample are the pairs a path draws together
    // (pixel jitter, direction samples): 32x32 cells.
    const auto bits = gpuBits(11);
    constexpr int N = 32;
    std::vector<double> observed(N * N, 0);
    double pairs = 0;
    for (uint32_t sample = 0; sample < SAMPLES; ++sample)
        for (uint32_t d = 0; d + 1 < DIMENSIONS; d += 2)
            for (uint32_t p = 0; p < PIXELS; ++p) {
                const uint32_t i = (sample * DIMENSIONS + d) * PIXELS + p;
                const float u = shared::uintToUnitFloat(bits[i]);
                const float v = shared::uintToUnitFloat(bits[i + PIXELS]);
                observed[static_cast<size_t>(u * N) * N + static_cast<size_t>(v * N)] += 1;
                pairs += 1;
            }
    std::vector<double> expected(N * N, pairs / (N * N));
    const auto result = test::chiSquareTest(observed, expected);
    EXPECT_GT(result.pValue, ALPHA)
        << "chi2 " << result.statistic << " dof " << result.degreesOfFreedom;
}

// The uniformity tests have power: a biased generator (u^1.02) is rejected.
TEST(Rng, ChiSquareRejectsSlightBias) {
    const auto bits = gpuBits(7);
    std::vector<double> observed(64, 0), expected(64, double(COUNT) / 64);
    for (uint32_t b : bits)
        observed[static_cast<size_t>(std::pow(shared::uintToUnitFloat(b), 1.02f) * 64)] += 1;
    EXPECT_LT(test::chiSquareTest(observed, expected).pValue, 1e-6);
}

}  // namespace
