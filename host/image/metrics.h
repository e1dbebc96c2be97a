// How far one image is from another (b is the reference): the numbers
// `vkpath compare` prints and the tests bound.
#pragma once

#include <array>
#include <cstdint>

#include "image/image.h"

namespace vkpath::image {

struct ChannelMetrics {
    double rmse = 0;              // sqrt(mean (a - b)^2)
    double relMse = 0;            // mean (a - b)^2 / (b^2 + 1e-2)
    double mae = 0;               // mean |a - b|
    double maxError = 0;          // max |a - b|
    uint32_t maxX = 0, maxY = 0;  // where maxError is (first such pixel)
    double psnr =
        0;  // 10 log10(1 / mse): a peak of 1, as for display-referred images; +inf if equal
    // relMSE without the TRIMMED_FRACTION of pixels whose own relMSE (mean of
    // their channels' terms) is largest: an error that a few fireflies cannot
    // dominate. Set for ImageMetrics::overall and by estimateErrorFromPair.
    double relMseTrimmed = 0;
};

struct ImageMetrics {
    std::array<ChannelMetrics, 3> channels;  // R, G, B
    ChannelMetrics overall;                  // over all channels of all finite pixels
    uint64_t nonFiniteA = 0;                 // pixels with a NaN or infinite channel in a
    uint64_t nonFiniteB = 0;
    uint64_t comparedPixels = 0;  // pixels finite in both, the ones measured
};

// The relative-MSE denominator's offset: keeps dark pixels from dominating.
inline constexpr double RELMSE_EPSILON = 1e-2;
// The share of pixels the trimmed relMSE leaves out (0.1%: 480 of 800 x 600).
inline constexpr double TRIMMED_FRACTION = 1e-3;

// Throws InputError if the sizes differ.
ImageMetrics compareImages(const Image& a, const Image& b);

// The error of `a` without a reference, from `b`, an independent render of
// the same image with the same settings (another seed). For unbiased,
// independent a and b of equal variance, E[(a - b)^2] = 2 Var(a) per pixel,
// so MSE(a) is estimated by mean (a - b)^2 / 2; relMSE divides each term by
// m^2 + RELMSE_EPSILON with m = (a + b) / 2 standing in for the unknown true
// value. Both see only variance: a bias common to a and b (clamping, a short
// max depth) is invisible. docs/TRADEOFFS.md derives the estimator's own bias.
// Only rmse and relMse are set. Throws InputError if the sizes differ.
ChannelMetrics estimateErrorFromPair(const Image& a, const Image& b);

// Per-pixel relative error mean_c |a - b| / (|b| + 0.01), as a false-colour
// image: log10 of the error from 1e-4 (dark blue) to 1 (yellow), non-finite
// pixels magenta.
Image errorHeatmap(const Image& a, const Image& b);

}  // namespace vkpath::image
