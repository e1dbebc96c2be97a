#include "image/metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>
#include <vector>

#include "input_error.h"

namespace vkpath::image {
namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

struct Accumulator {
    double sumSquared = 0, sumRelative = 0, sumAbsolute = 0, maxError = -1;
    uint32_t maxX = 0, maxY = 0;
    uint64_t count = 0;

    void add(double a, double b, uint32_t x, uint32_t y) {
        const double d = a - b;
        sumSquared += d * d;
        sumRelative += d * d / (b * b + RELMSE_EPSILON);
        sumAbsolute += std::abs(d);
        if (std::abs(d) > maxError) {
            maxError = std::abs(d);
            maxX = x;
            maxY = y;
        }
        ++count;
    }

    ChannelMetrics result() const {
        ChannelMetrics m;
        if (count == 0) return m;
        const double mse = sumSquared / double(count);
        m.rmse = std::sqrt(mse);
        m.relMse = sumRelative / double(count);
        m.mae = sumAbsolute / double(count);
        m.maxError = maxError;
        m.maxX = maxX;
        m.maxY = maxY;
        m.psnr = mse > 0 ? 10 * std::log10(1 / mse) : std::numeric_limits<double>::infinity();
        return m;
    }
};

// A few stops of a blue-green-yellow ramp (perceptually ordered, viridis-like).
glm::vec3 ramp(float t) {
    const glm::vec3 stops[] = {{0.267f, 0.005f, 0.329f},
                               {0.229f, 0.322f, 0.546f},
                               {0.128f, 0.567f, 0.551f},
                               {0.369f, 0.789f, 0.383f},
                               {0.993f, 0.906f, 0.144f}};
    t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
    const int i = std::min(3, int(t));
    return glm::mix(stops[i], stops[i + 1], t - float(i));
}

// The mean of `terms` without its largest TRIMMED_FRACTION (rounded down).
double trimmedMean(std::vector<double> terms) {
    if (terms.empty()) return 0;
    const size_t kept = terms.size() - size_t(double(terms.size()) * TRIMMED_FRACTION);
    std::nth_element(terms.begin(), terms.begin() + (kept - 1), terms.end());
    double sum = 0;
    for (size_t i = 0; i < kept; ++i) sum += terms[i];
    return sum / double(kept);
}

}  // namespace

ImageMetrics compareImages(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw InputError(fmt::format("image sizes differ: {}x{} and {}x{}", a.width, a.height,
                                     b.width, b.height));
    ImageMetrics metrics;
    std::array<Accumulator, 3> channels;
    Accumulator overall;
    std::vector<double> pixelRelMse;
    pixelRelMse.reserve(a.pixels.size());
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = 0; x < a.width; ++x) {
            const glm::vec3 pa = a.at(x, y), pb = b.at(x, y);
            const bool fa = finite(pa), fb = finite(pb);
            metrics.nonFiniteA += !fa;
            metrics.nonFiniteB += !fb;
            if (!fa || !fb) continue;
            ++metrics.comparedPixels;
            double relative = 0;
            for (int c = 0; c < 3; ++c) {
                channels[c].add(pa[c], pb[c], x, y);
                overall.add(pa[c], pb[c], x, y);
                const double d = double(pa[c]) - double(pb[c]);
                relative += d * d / (double(pb[c]) * pb[c] + RELMSE_EPSILON) / 3;
            }
            pixelRelMse.push_back(relative);
        }
    for (int c = 0; c < 3; ++c) metrics.channels[c] = channels[c].result();
    metrics.overall = overall.result();
    metrics.overall.relMseTrimmed = trimmedMean(std::move(pixelRelMse));
    return metrics;
}

ChannelMetrics estimateErrorFromPair(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw InputError(fmt::format("image sizes differ: {}x{} and {}x{}", a.width, a.height,
                                     b.width, b.height));
    double sumSquared = 0, sumRelative = 0;
    uint64_t count = 0;
    std::vector<double> pixelRelMse;
    pixelRelMse.reserve(a.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const glm::vec3 pa = a.pixels[i], pb = b.pixels[i];
        if (!finite(pa) || !finite(pb)) continue;
        double relative = 0;
        for (int c = 0; c < 3; ++c) {
            const double d = double(pa[c]) - double(pb[c]);
            const double m = (double(pa[c]) + double(pb[c])) / 2;
            sumSquared += d * d / 2;
            sumRelative += d * d / 2 / (m * m + RELMSE_EPSILON);
            relative += d * d / 2 / (m * m + RELMSE_EPSILON) / 3;
            ++count;
        }
        pixelRelMse.push_back(relative);
    }
    ChannelMetrics m;
    if (count == 0) return m;
    m.rmse = std::sqrt(sumSquared / double(count));
    m.relMse = sumRelative / double(count);
    m.relMseTrimmed = trimmedMean(std::move(pixelRelMse));
    return m;
}

Image errorHeatmap(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw InputError(fmt::format("image sizes differ: {}x{} and {}x{}", a.width, a.height,
                                     b.width, b.height));
    Image heat(a.width, a.height);
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const glm::vec3 pa = a.pixels[i], pb = b.pixels[i];
        if (!finite(pa) || !finite(pb)) {
            heat.pixels[i] = {1.0f, 0.0f, 1.0f};
            continue;
        }
        float error = 0;
        for (int c = 0; c < 3; ++c) error += std::abs(pa[c] - pb[c]) / (std::abs(pb[c]) + 0.01f);
        error /= 3;
        const float t = (std::log10(std::max(error, 1e-4f)) + 4.0f) / 4.0f;
        // The ramp is display-referred: undo the PNG writer's sRGB encoding.
        const glm::vec3 c = ramp(t);
        heat.pixels[i] = glm::pow(c, glm::vec3(2.2f));
    }
    return heat;
}

}  // namespace vkpath::image
