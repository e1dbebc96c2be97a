// Which samples a render takes next, for both integrators: every pixel alike
// (uniform), or, with adaptive sampling, more samples where the estimated
// error is largest; and when to stop at an error (--target-error).
//
// A render is a sequence of passes. A pass names its pixels (all of them, or
// an ascending list) and a number of rounds; in each round every pixel of the
// pass takes its next sample index (the range's first plus the samples it has
// so far), so a pixel's samples are always consecutive indices from the
// range's first and a pixel's sums are added in sample order. The renderers
// execute passes (GPU waves, CPU threads); this class chooses them from the
// film's per-pixel statistics, at pass ends only. Stops, the time budget and
// checkpoints come at whole rounds; the pass in progress is part of the state
// (RenderState::pass), so a render resumed from any checkpoint takes the same
// samples as the uninterrupted one.
//
// Adaptive sampling (RenderSettings::adaptive): after `adaptiveWarmup`
// uniform samples, each pass gives more samples to the pixels whose
// per-sample relative variance is largest: the allocation that minimises the
// image's relMSE for a number of samples takes n_p proportional to sqrt(v_p)
// (v_p: pixel p's per-sample variance over (mean^2 + 0.01), the relMSE's
// denominator), so the pixels with the largest sqrt(v_p) / n_p are sampled
// next. A pixel's v_p is the mean of its eight neighbours', not its own: a
// count decided from a pixel's own samples biases its mean (a pixel whose
// early samples all missed a rare bright path looks converged and stops dark;
// Kirk and Arvo 1991, "Unbiased sampling techniques for image synthesis"),
// while its neighbours' samples are independent of its own. What is left
// (a neighbour's count, and so its variance estimate, depends on the pixel
// through the neighbour's own neighbours) is second order; docs/ACCURACY.md,
// "Stopping at an error and adaptive sampling", measures it against references.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "shared/compat.h"
#include "wavefront/render_types.h"

namespace vkpath::wavefront {

// One pixel's estimate from the film: per channel the mean and the variance
// of that mean (estimatePixel), and its sample count.
struct PixelStatistics {
    glm::dvec3 mean{0.0};
    glm::dvec3 varianceOfMean{0.0};
    // With two sample streams (SceneInfo::sampleStreams): the variance of the
    // mean from the difference of the streams' means (streamVarianceOfMean),
    // which the error estimate takes instead of varianceOfMean.
    std::optional<glm::dvec3> streamVarianceOfMean;
};

// Where a target-error stop first measures the error: fewer samples give a
// variance estimate too rough to stop on (below 16 spp the bundled box's
// caustics are too rare for any estimate; at 1 spp there is no variance).
constexpr uint32_t FIRST_ERROR_CHECK = 16;

// The variance of a pixel's mean from its two streams, per channel: `sum` of
// its `samples` samples from index `first` on, `oddSum` of the odd-indexed
// ones. Owen-scrambled Sobol' points are not independent, so their sample
// variance overstates the error of their mean (4x at 256 spp on the diffuse
// box: docs/ACCURACY.md); two independent randomisations are, and for means
// m_e, m_o of n_e, n_o samples E[(m_e - m_o)^2] n_e n_o / n^2 is the
// variance of the whole mean (exact for independent samples, and for nets
// whose variance falls as a power of n when n_e = n_o). nullopt when one
// stream has no sample.
std::optional<glm::dvec3> streamVarianceOfMean(const glm::dvec3& sum, const glm::dvec3& oddSum,
                                               uint32_t first, uint32_t samples);

// The image's relMSE as `vkpath compare` measures it against the truth b
// (mean over pixels and channels of (a - b)^2 / (b^2 + 0.01)), estimated
// from each pixel's variance of its mean (from its two streams where it has
// them): E[(a - b)^2] = Var(a) for an unbiased a. b is the smaller of the
// pixel's own mean clamped to the range of its eight neighbours' means and
// their mean, but not below two standard errors under its own mean
// (relMseDenominators): a rare bright path that lifts a pixel's variance
// lifts its own mean with it, so with its own mean the term would stay small
// however far the pixel is from the truth; the neighbours' mean is free of
// its samples, and a pixel on an edge keeps its own. docs/ACCURACY.md
// measures the estimate against deep references.
double estimatedRelMse(const std::vector<PixelStatistics>& pixels, uint32_t width, uint32_t height);

// The render's image, its variance AOV and its estimated relMSE from the
// film's per-pixel statistics (both renderers end with this).
void takeImage(const std::vector<PixelStatistics>& pixels, uint32_t width, uint32_t height,
               RenderResult& result);

// Each pixel's mean, as an image (a preview of the render so far).
image::Image meanImage(const std::vector<PixelStatistics>& pixels, uint32_t width, uint32_t height);

// Per pixel and channel: b^2 + 0.01 of estimatedRelMse.
std::vector<glm::dvec3> relMseDenominators(const std::vector<PixelStatistics>& pixels,
                                           uint32_t width, uint32_t height);

// What the next pass of an adaptive render is, from the film's statistics,
// each pixel's sample count and the most samples a pixel may take
// (`maxSamples`); with `targetError`, the pixels the allocation for that
// relMSE still needs, and as many rounds as the estimate needs to reach it,
// each pixel's term falling as n^-decay (errorDecay).
// nullopt: every pixel is at `maxSamples`.
std::optional<SamplePass> planAdaptivePass(const std::vector<PixelStatistics>& pixels,
                                           const std::vector<uint32_t>& samples, uint32_t width,
                                           uint32_t height, uint32_t maxSamples,
                                           std::optional<double> targetError, double decay);

// The steepest the error falls with the samples n, as n^-b: 1 for the
// independent sampler, 3 for Sobol' points (sample_schedule.cpp).
double errorDecay(const RenderSettings& settings);

class SampleSchedule {
  public:
    // Continues `before` (an empty state: a render from its first sample)
    // of the range `samples`.
    SampleSchedule(const RenderSettings& settings, const SampleRange& samples,
                   const RenderState& before, uint64_t pixels);

    // The pass to render next (the one in progress first), or nullopt when
    // the render is done: the range used up, the target error reached or no
    // pixel left to sample. `statistics` gives the film's per-pixel
    // statistics (asked only when a decision needs them).
    std::optional<SamplePass> next(const std::function<std::vector<PixelStatistics>()>& statistics);

    // The current pass's pixels each took one more sample.
    void roundDone();

    // Samples pixel `pixel` has from the range's first (its next sample index
    // is the range's first plus this).
    uint32_t samplesOf(uint64_t pixel) const {
        return m_pixelSamples.empty() ? m_uniformSamples : m_pixelSamples[pixel];
    }
    // Samples every pixel has (the least of any pixel's).
    uint32_t wholeSamples() const;
    // The state's schedule fields: uniformSamples, pixelSamples and the pass in progress.
    void store(RenderState& state) const;
    // The estimate at the last decision that measured it (nullopt: none did).
    std::optional<double> lastEstimate() const { return m_lastEstimate; }
    // Whether the render ended because the estimate reached the target.
    bool reachedTarget() const { return m_reachedTarget; }
    // Sample-index rounds done and planned, for progress: (done, total) per
    // pixel; with adaptive sampling or a target error the total is a bound.
    uint32_t progressTotal() const { return m_samples.count; }

  private:
    RenderSettings m_settings;
    SampleRange m_samples;
    uint64_t m_pixels;
    uint32_t m_uniformSamples = 0;         // every pixel's, while sampling is uniform
    std::vector<uint32_t> m_pixelSamples;  // per pixel, once adaptive passes have begun
    std::optional<SamplePass> m_pass;      // in progress (roundsLeft > 0)
    std::optional<double> m_lastEstimate;
    bool m_reachedTarget = false;
};

}  // namespace vkpath::wavefront
