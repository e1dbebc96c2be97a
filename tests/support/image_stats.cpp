#include "support/image_stats.h"

#include <cmath>

#include "support/statistics.h"

namespace vkpath::test {

RegionMean regionMean(const image::Image& image, const image::Image& varianceOfMean,
                      const std::function<bool(uint32_t, uint32_t)>& select) {
    RegionMean r;
    double sum = 0, variance = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            if (!select(x, y)) continue;
            const glm::vec3 p = image.at(x, y), v = varianceOfMean.at(x, y);
            sum += (double(p.x) + p.y + p.z) / 3;
            // Var of the channel average; channels are correlated, so bound by
            // the worst case (perfect correlation): (sum of standard deviations / 3)^2.
            const double sd = (std::sqrt(double(v.x)) + std::sqrt(double(v.y)) + std::sqrt(double(v.z))) / 3;
            variance += sd * sd;
            ++r.pixels;
        }
    if (r.pixels == 0) return r;
    r.mean = sum / double(r.pixels);
    r.standardError = std::sqrt(variance) / double(r.pixels);
    return r;
}

double normalCritical(double alpha) {
    // Invert the two-sided tail 2 (1 - Phi(z)) = erfc(z / sqrt 2) by bisection.
    double lo = 0, hi = 40;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

BlockComparison compareBlocks(const image::Image& a, const image::Image& varA, const image::Image& b,
                              const image::Image& varB, uint32_t blockSize, double alpha) {
    BlockComparison c;
    const uint32_t bw = (a.width + blockSize - 1) / blockSize, bh = (a.height + blockSize - 1) / blockSize;
    c.blocks = int(bw * bh);
    const double critical = normalCritical(sidakAlpha(alpha, c.blocks));
    for (uint32_t by = 0; by < bh; ++by)
        for (uint32_t bx = 0; bx < bw; ++bx) {
            auto inBlock = [&](uint32_t x, uint32_t y) { return x / blockSize == bx && y / blockSize == by; };
            const RegionMean ma = regionMean(a, varA, inBlock), mb = regionMean(b, varB, inBlock);
            const double se = std::sqrt(ma.standardError * ma.standardError + mb.standardError * mb.standardError);
            const double diff = std::abs(ma.mean - mb.mean);
            const double z = se > 0 ? diff / se : (diff > 0 ? INFINITY : 0.0);
            c.worstZ = std::max(c.worstZ, z);
            c.rejected += z > critical;
        }
    return c;
}

}  // namespace vkpath::test
