#include "wavefront/sample_schedule.h"

#include <algorithm>
#include <cmath>

#include "image/metrics.h"

namespace vkpath::wavefront {
namespace {

// The median of `values` (reordered); 0 when empty.
template <typename T>
T median(std::vector<T>& values) {
    if (values.empty()) return T(0);
    auto middle = values.begin() + values.size() / 2;
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
}

}  // namespace

std::vector<glm::dvec3> relMseDenominators(const std::vector<PixelStatistics>& pixels,
                                           uint32_t width, uint32_t height) {
    std::vector<glm::dvec3> denominators(pixels.size());
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const size_t p = size_t(y) * width + x;
            glm::dvec3 least(INFINITY), most(-INFINITY), sum(0.0);
            int neighbours = 0;
            for (uint32_t ny = y ? y - 1 : 0; ny <= std::min(y + 1, height - 1); ++ny)
                for (uint32_t nx = x ? x - 1 : 0; nx <= std::min(x + 1, width - 1); ++nx) {
                    const size_t q = size_t(ny) * width + nx;
                    if (q == p) continue;
                    least = glm::min(least, pixels[q].mean);
                    most = glm::max(most, pixels[q].mean);
                    sum += pixels[q].mean;
                    ++neighbours;
                }
            // The smaller of the pixel's own mean clamped to its neighbours'
            // range and their mean (a 1x1 film has only its own): a path
            // that lifts a pixel's variance lifts its own mean with it, and
            // the neighbours' mean is free of its samples. Never below two
            // standard errors under its own mean: a peak that its own samples
            // establish (a highlight, a lamp's corner) keeps its value.
            const glm::dvec3 own = pixels[p].mean;
            glm::dvec3 m = own;
            if (neighbours > 0)
                m = glm::min(glm::clamp(own, least, most), glm::max(sum / double(neighbours), 0.0));
            m = glm::max(m, own - 2.0 * glm::sqrt(pixels[p].varianceOfMean));
            denominators[p] = m * m + image::RELMSE_EPSILON;
        }
    return denominators;
}

std::optional<glm::dvec3> streamVarianceOfMean(const glm::dvec3& sum, const glm::dvec3& oddSum,
                                               uint32_t first, uint32_t samples) {
    // Odd indices in [first, first + samples).
    const uint64_t odd = ((uint64_t(first) + samples) >> 1) - (first >> 1);
    const uint64_t even = samples - odd;
    if (odd == 0 || even == 0) return std::nullopt;
    const glm::dvec3 difference = (sum - oddSum) / double(even) - oddSum / double(odd);
    return difference * difference * (double(even) * double(odd) / (double(samples) * samples));
}

double estimatedRelMse(const std::vector<PixelStatistics>& pixels, uint32_t width,
                       uint32_t height) {
    const std::vector<glm::dvec3> denominators = relMseDenominators(pixels, width, height);
    double sum = 0;
    for (size_t p = 0; p < pixels.size(); ++p) {
        const glm::dvec3 variance =
            pixels[p].streamVarianceOfMean.value_or(pixels[p].varianceOfMean);
        for (int c = 0; c < 3; ++c) sum += variance[c] / denominators[p][c];
    }
    return pixels.empty() ? 0.0 : sum / (3.0 * double(pixels.size()));
}

image::Image meanImage(const std::vector<PixelStatistics>& pixels, uint32_t width,
                       uint32_t height) {
    image::Image image(width, height);
    for (size_t i = 0; i < pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) image.pixels[i][c] = float(pixels[i].mean[c]);
    return image;
}

void takeImage(const std::vector<PixelStatistics>& pixels, uint32_t width, uint32_t height,
               RenderResult& result) {
    result.estimatedRelMse = estimatedRelMse(pixels, width, height);
    result.image = meanImage(pixels, width, height);
    result.varianceOfMean = image::Image(width, height);
    for (size_t i = 0; i < pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            result.varianceOfMean.pixels[i][c] = float(pixels[i].varianceOfMean[c]);
}

// The steepest the error falls with the samples n, as n^-b: b = 1 for
// independent samples; Sobol' points converge faster where the integrand
// is smooth, most of all as a stream's count reaches a power of two (on
// CBempty the estimate fell by 1.7x from 56 to 64 spp, b = 4 there). The
// stop looks again where the error falling this fast would reach the
// target: looking where a slower fall would reach it stopped on CBempty at
// 64 spp and 0.51 of the target.
double errorDecay(const RenderSettings& settings) {
    return settings.sampler == SamplerKind::Sobol ? 3.0 : 1.0;
}

std::optional<SamplePass> planAdaptivePass(const std::vector<PixelStatistics>& pixels,
                                           const std::vector<uint32_t>& samples, uint32_t width,
                                           uint32_t height, uint32_t maxSamples,
                                           std::optional<double> targetError, double decay) {
    const size_t count = size_t(width) * height;
    // Each pixel's per-sample variance over its own mean squared (plus
    // 0.01), a function of its own samples alone.
    std::vector<double> own(count);
    for (size_t p = 0; p < count; ++p) {
        double sum = 0;
        for (int c = 0; c < 3; ++c)
            sum += pixels[p].varianceOfMean[c] /
                   (pixels[p].mean[c] * pixels[p].mean[c] + image::RELMSE_EPSILON);
        own[p] = samples[p] * sum / 3;
    }
    // v_p as the mean of its eight neighbours' (a pixel's own samples take
    // no part in its decision; a 1x1 film has only its own).
    std::vector<double> variance(count);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const size_t p = size_t(y) * width + x;
            double sum = 0;
            int n = 0;
            for (uint32_t ny = y ? y - 1 : 0; ny <= std::min(y + 1, height - 1); ++ny)
                for (uint32_t nx = x ? x - 1 : 0; nx <= std::min(x + 1, width - 1); ++nx) {
                    const size_t q = size_t(ny) * width + nx;
                    if (q == p) continue;
                    sum += own[q];
                    ++n;
                }
            variance[p] = n > 0 ? sum / n : own[p];
        }
    // The optimal allocation equalises sqrt(v_p) / n_p: the pixels where it
    // is largest gain the most from a sample.
    std::vector<double> score(count);
    std::vector<double> open;  // scores of the pixels below maxSamples
    double sumRoots = 0;
    for (size_t p = 0; p < count; ++p) {
        const double root = std::sqrt(variance[p]);
        sumRoots += root;
        score[p] = root / std::max<uint32_t>(samples[p], 1);
        if (samples[p] < maxSamples) open.push_back(score[p]);
    }
    if (open.empty()) return std::nullopt;
    // With a target E: the allocation reaching E with the fewest samples is
    // n_p = sqrt(v_p) / tau with tau = P E / sum_q sqrt(v_q); a pixel with a
    // score above tau is short of it. Without one: the better half (the
    // pixels scoring at least the median).
    const std::optional<double> tau =
        targetError ? std::optional<double>(double(count) * *targetError / sumRoots) : std::nullopt;
    // The schedule asks only while the estimate is above the target, which
    // the neighbours' variances may not show (they are not the estimate's
    // own terms): then the better half too.
    std::vector<uint32_t> active;
    if (tau)
        for (size_t p = 0; p < count; ++p)
            if (samples[p] < maxSamples && score[p] > *tau) active.push_back(uint32_t(p));
    if (active.empty()) {
        const double half = median(open);
        for (size_t p = 0; p < count; ++p)
            if (samples[p] < maxSamples && score[p] >= half) active.push_back(uint32_t(p));
    }
    // Rounds: at most as many as the median active pixel has (the schedule
    // at most doubles a pixel's samples before it looks again); without a
    // target, half that; with one, the fewest that bring the estimate
    // (estimatedRelMse's terms, each falling as n^-decay) to the
    // target, so that the last pass ends near it rather than far below.
    std::vector<uint32_t> have;
    for (uint32_t p : active) have.push_back(samples[p]);
    const uint32_t mostRounds = std::max<uint32_t>(median(have), 1);
    uint32_t rounds = std::max<uint32_t>(mostRounds / 2, 1);
    if (targetError) {
        const std::vector<glm::dvec3> denominators = relMseDenominators(pixels, width, height);
        std::vector<double> term(count);
        double rest = 0;  // the terms of the pixels the pass leaves alone
        for (size_t p = 0; p < count; ++p) {
            const glm::dvec3 t =
                pixels[p].streamVarianceOfMean.value_or(pixels[p].varianceOfMean) / denominators[p];
            term[p] = (t.x + t.y + t.z) / 3;
            rest += term[p];
        }
        for (uint32_t p : active) rest -= term[p];
        auto predicted = [&](uint32_t k) {
            double sum = rest;
            for (uint32_t p : active)
                sum += term[p] * std::pow(samples[p] / (double(samples[p]) + k), decay);
            return sum / double(count);
        };
        uint32_t low = 1, high = mostRounds;
        while (low < high) {
            const uint32_t middle = low + (high - low) / 2;
            if (predicted(middle) <= *targetError)
                high = middle;
            else
                low = middle + 1;
        }
        rounds = low;
    }
    // Pixels that `rounds` would take past maxSamples wait for a shorter pass;
    // if that is all of them, the pass is as long as the nearest one allows.
    std::vector<uint32_t> fit;
    uint32_t room = maxSamples;
    for (uint32_t p : active) {
        room = std::min(room, maxSamples - samples[p]);
        if (maxSamples - samples[p] >= rounds) fit.push_back(p);
    }
    if (fit.empty()) return SamplePass{std::move(active), room};
    return SamplePass{std::move(fit), rounds};
}

SampleSchedule::SampleSchedule(const RenderSettings& settings, const SampleRange& samples,
                               const RenderState& before, uint64_t pixels)
    : m_settings(settings),
      m_samples(samples),
      m_pixels(pixels),
      m_uniformSamples(before.samplesDone),
      m_pixelSamples(before.pixelSamples),
      m_pass(before.pass) {
    // A uniform pass in progress ends at the sample count this render asks
    // (a resumed render may ask fewer or more than the one that stopped).
    if (m_pass && m_pass->pixels.empty())
        m_pass->rounds =
            std::min(m_pass->rounds, m_samples.count - std::min(m_samples.count, m_uniformSamples));
}

std::optional<SamplePass> SampleSchedule::next(
    const std::function<std::vector<PixelStatistics>()>& statistics) {
    if (m_pass && m_pass->rounds > 0) return m_pass;
    m_pass.reset();
    const std::optional<double> target = m_settings.targetError;
    const uint32_t uniformEnd = m_settings.adaptive
                                    ? std::min(m_samples.count, m_settings.adaptiveWarmup)
                                    : m_samples.count;
    // Measures the error; true when it has reached the target.
    auto measure = [&](const std::vector<PixelStatistics>& stats) {
        m_lastEstimate = estimatedRelMse(stats, m_settings.width, m_settings.height);
        m_reachedTarget = target && *m_lastEstimate <= *target;
        return m_reachedTarget;
    };
    if (m_pixelSamples.empty() && m_uniformSamples < uniformEnd) {
        uint32_t until = uniformEnd;
        if (target) {
            const uint32_t n = m_uniformSamples;
            if (n < FIRST_ERROR_CHECK) {
                until = std::min(uniformEnd, FIRST_ERROR_CHECK);
            } else {
                if (measure(statistics())) return std::nullopt;
                // Where the error, falling at its steepest, would reach E
                // (errorDecay); at most twice as far, so that a rough early
                // estimate cannot overshoot far.
                const double reach = std::ceil(
                    double(n) * std::pow(*m_lastEstimate / *target, 1.0 / errorDecay(m_settings)));
                until = uint32_t(std::min<double>(
                    {double(uniformEnd), std::max(reach, double(n) + 1), 2.0 * n}));
            }
        }
        m_pass = SamplePass{{}, until - m_uniformSamples};
        return m_pass;
    }
    if (!target && !m_settings.adaptive) return std::nullopt;
    const std::vector<PixelStatistics> stats = statistics();
    if (measure(stats) || !m_settings.adaptive) return std::nullopt;
    if (m_pixelSamples.empty()) m_pixelSamples.assign(m_pixels, m_uniformSamples);
    m_pass = planAdaptivePass(stats, m_pixelSamples, m_settings.width, m_settings.height,
                              m_samples.count, target, errorDecay(m_settings));
    return m_pass;
}

void SampleSchedule::roundDone() {
    if (m_pass->pixels.empty())
        ++m_uniformSamples;
    else
        for (uint32_t p : m_pass->pixels) ++m_pixelSamples[p];
    --m_pass->rounds;
}

uint32_t SampleSchedule::wholeSamples() const {
    if (m_pixelSamples.empty()) return m_uniformSamples;
    return *std::min_element(m_pixelSamples.begin(), m_pixelSamples.end());
}

void SampleSchedule::store(RenderState& state) const {
    state.samplesDone = wholeSamples();
    state.pixelSamples = m_pixelSamples;
    state.pass = m_pass && m_pass->rounds > 0 ? m_pass : std::nullopt;
}

}  // namespace vkpath::wavefront
