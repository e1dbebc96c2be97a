#include "image/statistics.h"

#include <fmt/format.h>

#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <vector>

#include "input_error.h"

namespace vkpath::image {
namespace {

// One pixel's channel average and the (worst-case) variance of it.
struct PixelTerms {
    double mean;
    double variance;
};

PixelTerms pixelTerms(glm::vec3 p, glm::vec3 v) {
    const double sd =
        (std::sqrt(double(v.x)) + std::sqrt(double(v.y)) + std::sqrt(double(v.z))) / 3;
    return {(double(p.x) + p.y + p.z) / 3, sd * sd};
}

void requireSameSize(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height)
        throw InputError(fmt::format("{}: {}x{} and {}x{} differ in size", what, a.width, a.height,
                                     b.width, b.height));
}

}  // namespace

std::filesystem::path aovPath(const std::filesystem::path& output, const std::string& aov) {
    auto path = output;
    path.replace_filename(
        fmt::format("{}.{}{}", output.stem().string(), aov, output.extension().string()));
    return path;
}

RegionMean regionMean(const Image& image, const Image& varianceOfMean,
                      const std::function<bool(uint32_t, uint32_t)>& select) {
    requireSameSize(image, varianceOfMean, "image and its variance");
    RegionMean r;
    double sum = 0, variance = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            if (!select(x, y)) continue;
            const PixelTerms t = pixelTerms(image.at(x, y), varianceOfMean.at(x, y));
            sum += t.mean;
            variance += t.variance;
            ++r.pixels;
        }
    if (r.pixels == 0) return r;
    r.mean = sum / double(r.pixels);
    r.standardError = std::sqrt(variance) / double(r.pixels);
    return r;
}

double sidakAlpha(double alpha, uint64_t tests) {
    return tests == 0 ? alpha : 1.0 - std::pow(1.0 - alpha, 1.0 / double(tests));
}

double normalCritical(double alpha) {
    // The upper alpha/2 quantile: 1 - Phi(z) = alpha / 2.
    return boost::math::quantile(
        boost::math::complement(boost::math::normal_distribution<double>(), alpha / 2));
}

BlockComparison compareBlocks(const Image& a, const Image& varianceA, const Image& b,
                              const Image& varianceB, uint32_t blockSize, double alpha) {
    requireSameSize(a, b, "images");
    requireSameSize(a, varianceA, "image A and its variance");
    requireSameSize(b, varianceB, "image B and its variance");
    if (blockSize == 0) throw InputError("block size must be at least 1");
    if (!(alpha > 0 && alpha < 1))
        throw InputError(fmt::format("alpha {} is not in (0, 1)", alpha));

    const uint32_t bw = (a.width + blockSize - 1) / blockSize,
                   bh = (a.height + blockSize - 1) / blockSize;
    // Per block: sums of the channel averages and of their variances, for A and B.
    struct Sums {
        double meanA = 0, varianceA = 0, meanB = 0, varianceB = 0;
        uint64_t pixels = 0;
    };
    std::vector<Sums> blocks(size_t(bw) * bh);
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = 0; x < a.width; ++x) {
            Sums& s = blocks[size_t(y / blockSize) * bw + x / blockSize];
            const PixelTerms ta = pixelTerms(a.at(x, y), varianceA.at(x, y));
            const PixelTerms tb = pixelTerms(b.at(x, y), varianceB.at(x, y));
            s.meanA += ta.mean;
            s.varianceA += ta.variance;
            s.meanB += tb.mean;
            s.varianceB += tb.variance;
            ++s.pixels;
        }

    BlockComparison c;
    c.blocks = int(blocks.size());
    c.alpha = alpha;
    c.critical = normalCritical(sidakAlpha(alpha, blocks.size()));
    for (size_t i = 0; i < blocks.size(); ++i) {
        const Sums& s = blocks[i];
        const double n = double(s.pixels);
        // se of a block mean: sqrt(sum of variances) / n; for the difference, add in quadrature.
        const double se = std::sqrt(s.varianceA + s.varianceB) / n;
        const double diff = std::abs(s.meanA - s.meanB) / n;
        double z;
        if (!std::isfinite(diff) || !std::isfinite(se))
            z = INFINITY;
        else
            z = se > 0 ? diff / se : (diff > 0 ? INFINITY : 0.0);
        if (z > c.worstZ) {
            c.worstZ = z;
            c.worstX = uint32_t(i % bw) * blockSize;
            c.worstY = uint32_t(i / bw) * blockSize;
        }
        c.rejected += z > c.critical;
    }
    return c;
}

}  // namespace vkpath::image
