// Judging renders statistically: the mean of a region against an exact value
// (a z-test with the standard error from the variance AOV), and two renders
// against each other block by block (Welch z-tests with a Sidak correction).
#pragma once

#include <cstdint>
#include <functional>

#include "image/image.h"

namespace vkpath::test {

struct RegionMean {
    double mean = 0;           // of the average of the three channels
    double standardError = 0;  // from the per-pixel variance of the mean
    uint64_t pixels = 0;
};

// Over pixels where `select(x, y)` is true.
RegionMean regionMean(const image::Image& image, const image::Image& varianceOfMean,
                      const std::function<bool(uint32_t, uint32_t)>& select);

struct BlockComparison {
    int blocks = 0;
    int rejected = 0;      // blocks whose means differ at the corrected significance
    double worstZ = 0;
};

// Splits both images into blocks x blocks pixel blocks and tests each
// block's channel-averaged mean for equality (|z| against the two-sided
// Sidak-corrected critical value for `alpha` over all blocks).
BlockComparison compareBlocks(const image::Image& a, const image::Image& varA, const image::Image& b,
                              const image::Image& varB, uint32_t blockSize, double alpha);

// The two-sided standard normal critical value for significance alpha.
double normalCritical(double alpha);

}  // namespace vkpath::test
