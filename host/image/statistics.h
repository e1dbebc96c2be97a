// Judging renders statistically, with the standard errors that the variance
// AOV measures (per pixel and channel, the variance of the pixel's mean):
// the mean of a region against an exact value, and two independent renders
// against each other block by block, each block a two-sample z-test, the
// blocks together held to a false-alarm rate by the Sidak correction (as
// Mitsuba 3's render tests do per pixel). `vkpath compare --ztest` and the
// tests use these.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "image/image.h"

namespace vkpath::image {

// Where `vkpath render -o OUTPUT --aov NAME` writes an AOV, beside the render:
// "out/x.exr" + "variance" -> "out/x.variance.exr".
std::filesystem::path aovPath(const std::filesystem::path& output, const std::string& aov);

struct RegionMean {
    double mean = 0;           // of the average of the three channels
    double standardError = 0;  // from the per-pixel variance of the mean
    uint64_t pixels = 0;
};

// Over the pixels where `select(x, y)` is true. The channels of a pixel are
// correlated (the same paths), so the variance of their average is bounded
// by the worst case, perfect correlation: ((sd_r + sd_g + sd_b) / 3)^2.
RegionMean regionMean(const Image& image, const Image& varianceOfMean,
                      const std::function<bool(uint32_t, uint32_t)>& select);

// Per-test significance so that `tests` independent tests together reject a
// true hypothesis with probability `alpha` (Sidak): 1 - (1 - alpha)^(1/tests).
double sidakAlpha(double alpha, uint64_t tests);

// The two-sided standard normal critical value z with P(|Z| > z) = alpha, for
// alpha in (0, 1] (Boost.Math's normal quantile).
double normalCritical(double alpha);

struct BlockComparison {
    int blocks = 0;     // blockSize x blockSize blocks (partial ones at the right and bottom edges)
    int rejected = 0;   // blocks whose means differ at the corrected significance
    double worstZ = 0;  // largest |z| (+inf for a block with a NaN or infinite pixel)
    uint32_t worstX = 0;  // top-left pixel of the block with the largest |z|
    uint32_t worstY = 0;
    double critical = 0;  // the Sidak-corrected two-sided critical value of |z|
    double alpha = 0;     // the family-wise false-alarm rate asked for
};

// Whether two independent renders (different seeds) estimate the same image:
// per block, z = (mean_a - mean_b) / sqrt(se_a^2 + se_b^2) of the
// channel-averaged block means, rejected when |z| exceeds the critical value
// for the Sidak-corrected alpha over all blocks. A block holding a NaN or
// infinite pixel (image or variance) is rejected. Throws InputError when the
// four images differ in size or blockSize is 0; alpha must lie in (0, 1).
BlockComparison compareBlocks(const Image& a, const Image& varianceA, const Image& b,
                              const Image& varianceB, uint32_t blockSize, double alpha);

}  // namespace vkpath::image
