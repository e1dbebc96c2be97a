// The block z-test of host/image/statistics.h on synthetic images whose
// truth is known: pixel means drawn from a normal distribution with the
// stated variance of the mean, so the test's false-alarm rate and power can
// be checked against theory without rendering.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "image/statistics.h"
#include "input_error.h"

namespace {

using namespace vkpath;

struct Render {
    image::Image image, variance;
};

// Every pixel and channel: truth + offset + N(0, sigma^2), variance AOV sigma^2.
Render synthetic(uint32_t w, uint32_t h, float truth, float offset, float sigma, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, sigma > 0.0f ? sigma : 1.0f);
    Render r{image::Image(w, h), image::Image(w, h)};
    for (size_t i = 0; i < r.image.pixels.size(); ++i) {
        // The same noise in the three channels: perfectly correlated, the
        // case regionMean's variance bound is exact for.
        r.image.pixels[i] = glm::vec3(truth + offset + (sigma > 0.0f ? noise(rng) : 0.0f));
        r.variance.pixels[i] = glm::vec3(sigma * sigma);
    }
    return r;
}

TEST(BlockZTest, CriticalValuesAreTheNormalQuantiles) {
    EXPECT_NEAR(image::normalCritical(0.05), 1.959964, 1e-5);
    EXPECT_NEAR(image::normalCritical(0.01), 2.575829, 1e-5);
    EXPECT_NEAR(image::sidakAlpha(0.01, 1), 0.01, 1e-15);
    EXPECT_NEAR(image::sidakAlpha(0.01, 100), 1.0 - std::pow(0.99, 0.01), 1e-15);
}

// 200 pairs of equal images of 30 blocks at alpha 0.05: the family-wise
// false-alarm count is Binomial(200, 0.05) (mean 10, sd 3.1); 25 is 4.9 sd
// above it. And no more rejections than that: the test is not too lax either
// (at alpha 0.5 about half the pairs must be rejected).
TEST(BlockZTest, FalseAlarmRateIsAlpha) {
    int alarms05 = 0, alarms50 = 0;
    for (uint32_t trial = 0; trial < 200; ++trial) {
        const Render a = synthetic(48, 40, 1.0f, 0.0f, 0.1f, 2 * trial + 1);
        const Render b = synthetic(48, 40, 1.0f, 0.0f, 0.1f, 2 * trial + 2);
        alarms05 +=
            image::compareBlocks(a.image, a.variance, b.image, b.variance, 8, 0.05).rejected > 0;
        alarms50 +=
            image::compareBlocks(a.image, a.variance, b.image, b.variance, 8, 0.5).rejected > 0;
    }
    EXPECT_LE(alarms05, 25);
    EXPECT_GE(alarms50, 70);  // Binomial(200, 0.5): mean 100, sd 7.1
    EXPECT_LE(alarms50, 130);
}

// A shift of 0.02 where a block mean's standard error is 0.1 / 8 = 0.0125
// (z of the difference ~1.1 per block) is too small to see; a shift of 0.1
// (z ~5.7 per block, critical ~3.6 for 30 blocks) is seen in nearly every block.
TEST(BlockZTest, PowerGrowsWithTheShift) {
    const Render a = synthetic(48, 40, 1.0f, 0.0f, 0.1f, 11);
    const Render small = synthetic(48, 40, 1.0f, 0.02f, 0.1f, 12);
    const Render large = synthetic(48, 40, 1.0f, 0.1f, 0.1f, 13);
    const auto none =
        image::compareBlocks(a.image, a.variance, small.image, small.variance, 8, 0.01);
    const auto most =
        image::compareBlocks(a.image, a.variance, large.image, large.variance, 8, 0.01);
    EXPECT_EQ(none.blocks, 30);
    EXPECT_LE(none.rejected, 3);
    EXPECT_GE(most.rejected, 27);
    EXPECT_NEAR(most.critical, image::normalCritical(image::sidakAlpha(0.01, 30)), 1e-12);
    EXPECT_GT(most.worstZ, most.critical);
}

TEST(BlockZTest, ANonFinitePixelRejectsItsBlock) {
    Render a = synthetic(16, 16, 1.0f, 0.0f, 0.1f, 1);
    const Render b = synthetic(16, 16, 1.0f, 0.0f, 0.1f, 2);
    a.image.at(9, 3).y = std::nanf("");
    const auto c = image::compareBlocks(a.image, a.variance, b.image, b.variance, 8, 0.01);
    EXPECT_EQ(c.rejected, 1);
    EXPECT_TRUE(std::isinf(c.worstZ));
    EXPECT_EQ(c.worstX, 8u);
    EXPECT_EQ(c.worstY, 0u);
}

TEST(BlockZTest, EqualNoiselessImagesAgreeAndDifferentOnesDoNot) {
    const Render a = synthetic(8, 8, 1.0f, 0.0f, 0.0f, 1);
    const Render b = synthetic(8, 8, 1.0f, 1e-3f, 0.0f, 1);
    EXPECT_EQ(image::compareBlocks(a.image, a.variance, a.image, a.variance, 8, 0.01).rejected, 0);
    EXPECT_EQ(image::compareBlocks(a.image, a.variance, b.image, b.variance, 8, 0.01).rejected, 1);
}

TEST(BlockZTest, BadArgumentsAreInputErrors) {
    const Render a = synthetic(8, 8, 1.0f, 0.0f, 0.1f, 1);
    const Render b = synthetic(8, 4, 1.0f, 0.0f, 0.1f, 1);
    EXPECT_THROW(image::compareBlocks(a.image, a.variance, b.image, b.variance, 8, 0.01),
                 InputError);
    EXPECT_THROW(image::compareBlocks(a.image, b.variance, a.image, a.variance, 8, 0.01),
                 InputError);
    EXPECT_THROW(image::compareBlocks(a.image, a.variance, a.image, a.variance, 0, 0.01),
                 InputError);
    EXPECT_THROW(image::compareBlocks(a.image, a.variance, a.image, a.variance, 8, 1.5),
                 InputError);
}

TEST(BlockZTest, AovPathIsBesideTheRender) {
    EXPECT_EQ(image::aovPath("out/x.exr", "variance"), std::filesystem::path("out/x.variance.exr"));
    EXPECT_EQ(image::aovPath("y.hdr", "variance"), std::filesystem::path("y.variance.hdr"));
}

}  // namespace
