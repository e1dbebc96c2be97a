#include "scene/environment_table.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace vkpath::scene {

double luminance(const glm::vec3& rgb) { return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z; }

EnvironmentTable buildEnvironmentTable(const image::Image& map) {
    EnvironmentTable table;
    const size_t count = map.pixels.size();
    std::vector<double> weights(count);
    for (uint32_t y = 0; y < map.height; ++y) {
        const double sinTheta = std::sin(std::numbers::pi * (y + 0.5) / map.height);
        for (uint32_t x = 0; x < map.width; ++x) {
            const size_t i = size_t(y) * map.width + x;
            weights[i] = std::max(0.0, luminance(map.pixels[i])) * sinTheta;
            table.totalWeight += weights[i];
        }
    }
    if (!(table.totalWeight > 0) || count == 0) return table;

    // Vose's alias method on scaled probabilities q_i = N p_i (mean 1).
    std::vector<double> q(count);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < count; ++i) {
        q[i] = weights[i] / table.totalWeight * double(count);
        (q[i] < 1.0 ? small : large).push_back(uint32_t(i));
    }
    table.entries.resize(count);
    std::vector<double> keep(count, 1.0);
    for (size_t i = 0; i < count; ++i) table.entries[i].alias = uint32_t(i);
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back(), l = large.back();
        small.pop_back();
        keep[s] = q[s];
        table.entries[s].alias = l;
        q[l] -= 1.0 - q[s];
        if (q[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What remains in either list keeps its whole bucket (q rounds to 1).

    const auto brightest = uint32_t(std::max_element(weights.begin(), weights.end()) - weights.begin());
    // Quantise: a bucket keeps its texel when 32 random bits < threshold.
    constexpr double SCALE = 4294967296.0;  // 2^32
    for (size_t i = 0; i < count; ++i) {
        double t = std::round(keep[i] * SCALE);
        uint64_t threshold = t >= SCALE ? (uint64_t(1) << 32) : uint64_t(t);
        if (weights[i] > 0 && threshold == 0) threshold = 1;  // never lose a texel with radiance
        if (weights[i] == 0) {
            threshold = 0;
            // A zero-weight texel left over by rounding must not alias itself.
            if (table.entries[i].alias == i) table.entries[i].alias = brightest;
        }
        // 2^32 does not fit: a bucket that always keeps its texel aliases to itself.
        if (threshold == (uint64_t(1) << 32)) {
            table.entries[i].threshold = 0xffffffffu;
            table.entries[i].alias = uint32_t(i);
        } else {
            table.entries[i].threshold = uint32_t(threshold);
        }
    }
    // Exact probabilities of the quantised table: bucket i gives texel i
    // `threshold` of the 2^32 outcomes of its bits and its alias the rest.
    std::vector<uint64_t> outcomes(count, 0);
    for (size_t i = 0; i < count; ++i) {
        const shared::EnvAliasEntry& e = table.entries[i];
        outcomes[i] += e.threshold;
        outcomes[e.alias] += (uint64_t(1) << 32) - e.threshold;
    }
    for (size_t i = 0; i < count; ++i)
        table.entries[i].probability = float(double(outcomes[i]) / (double(count) * SCALE));
    return table;
}

}  // namespace vkpath::scene
