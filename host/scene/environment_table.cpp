#include "scene/environment_table.h"

#include <cmath>
#include <numbers>

#include "scene/alias_table.h"

namespace vkpath::scene {

double luminance(const glm::vec3& rgb) {
    return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
}

RowWeights bilinearRowWeights(uint32_t row, uint32_t height) {
    // The cell spans [c - h, c + h] in v around the row's centre c. Above c the
    // radiance runs linearly from the previous row's centre (c - 2h) to this
    // one, so the previous row has the weight (c - v) / 2h; below c the next row
    // has (v - c) / 2h. With t = |v - c|, sin(pi v) = sin(pi c) cos(pi t) -+
    // cos(pi c) sin(pi t), and the moments of t over [0, h] are closed forms:
    //   A = int t cos(pi t) dt = h sin(pi h) / pi - 2 sin^2(pi h / 2) / pi^2,
    //   B = int t sin(pi t) dt = sin(pi h) / pi^2 - h cos(pi h) / pi.
    // (Written around the centre, with no difference of cosines of nearby
    // angles: the relative error stays near 1e-9 even for rows at the poles.)
    constexpr double PI = std::numbers::pi;
    const double h = 0.5 / height, c = (row + 0.5) / height;
    const double sinC = std::sin(PI * c), cosC = std::cos(PI * c);
    const double sinH = std::sin(PI * h), cosH = std::cos(PI * h), sinHalfH = std::sin(PI * h / 2);
    const double a = h * sinH / PI - 2 * sinHalfH * sinHalfH / (PI * PI);
    const double b = sinH / (PI * PI) - h * cosH / PI;
    RowWeights w;
    w.previous = (sinC * a - cosC * b) / (2 * h);
    w.next = (sinC * a + cosC * b) / (2 * h);
    // The integral of sin(pi v) over the whole cell, less the neighbours' shares.
    w.self = 2 * sinC * sinH / PI - w.previous - w.next;
    return w;
}

EnvironmentTable buildEnvironmentTable(const image::Image& map) {
    const uint32_t width = map.width, height = map.height;
    // U[r][i] = the integral over cell column i of row r's radiance
    // interpolated in u (periodic), in luminance: the neighbours' centres lie
    // a texel away, so over the cell each has the weight 1/8 and the texel 3/4.
    std::vector<double> lum(map.pixels.size()), rowIntegral(map.pixels.size());
    for (size_t i = 0; i < lum.size(); ++i) lum[i] = std::max(0.0, luminance(map.pixels[i]));
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const size_t row = size_t(y) * width;
            const double left = lum[row + (x + width - 1) % width],
                         right = lum[row + (x + 1) % width];
            rowIntegral[row + x] = (0.125 * left + 0.75 * lum[row + x] + 0.125 * right) / width;
        }
    EnvironmentTable table;
    std::vector<double> weights(map.pixels.size());
    for (uint32_t y = 0; y < height; ++y) {
        const RowWeights w = bilinearRowWeights(y, height);
        // Beyond the first and last rows the radiance is clamped to them.
        const uint32_t previous = y == 0 ? 0 : y - 1, next = y + 1 == height ? y : y + 1;
        for (uint32_t x = 0; x < width; ++x) {
            const size_t i = size_t(y) * width + x;
            weights[i] = w.previous * rowIntegral[size_t(previous) * width + x] +
                         w.self * rowIntegral[i] + w.next * rowIntegral[size_t(next) * width + x];
            table.totalWeight += weights[i];
        }
    }
    table.entries = buildAliasTable(weights);
    return table;
}

}  // namespace vkpath::scene
