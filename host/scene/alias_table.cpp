#include "scene/alias_table.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vkpath::scene {

std::vector<shared::AliasEntry> buildAliasTable(std::span<const double> rawWeights) {
    const size_t count = rawWeights.size();
    std::vector<double> weights(count);
    double total = 0;
    for (size_t i = 0; i < count; ++i) {
        weights[i] = std::isfinite(rawWeights[i]) && rawWeights[i] > 0 ? rawWeights[i] : 0.0;
        total += weights[i];
    }
    std::vector<shared::AliasEntry> entries;
    if (!(total > 0) || !std::isfinite(total)) return entries;

    // Vose's alias method on scaled probabilities q_i = N p_i (mean 1).
    std::vector<double> q(count), keep(count, 1.0);
    std::vector<uint32_t> small, large;
    entries.resize(count);
    for (size_t i = 0; i < count; ++i) {
        q[i] = weights[i] / total * double(count);
        (q[i] < 1.0 ? small : large).push_back(uint32_t(i));
        entries[i].alias = uint32_t(i);
    }
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back(), l = large.back();
        small.pop_back();
        keep[s] = q[s];
        entries[s].alias = l;
        q[l] -= 1.0 - q[s];
        if (q[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // Whatever remains in either list keeps its whole bucket (its q is 1 up to rounding).

    const auto heaviest =
        uint32_t(std::max_element(weights.begin(), weights.end()) - weights.begin());
    constexpr double SCALE = 4294967296.0;  // 2^32
    for (size_t i = 0; i < count; ++i) {
        const double t = std::round(keep[i] * SCALE);
        uint64_t threshold = t >= SCALE ? (uint64_t(1) << 32) : uint64_t(t);
        if (weights[i] > 0 && threshold == 0) threshold = 1;  // never lose an element
        if (weights[i] == 0) {
            threshold = 0;
            // A zero-weight element left over by rounding must not alias itself.
            if (entries[i].alias == i) entries[i].alias = heaviest;
        }
        if (threshold == (uint64_t(1) << 32)) {
            // 2^32 does not fit in 32 bits: keep the bucket whole by aliasing to itself.
            entries[i].threshold = 0xffffffffu;
            entries[i].alias = uint32_t(i);
        } else {
            entries[i].threshold = uint32_t(threshold);
        }
    }
    // Exact probabilities of the quantised table: bucket i gives element i
    // `threshold` of the 2^32 outcomes of its bits and its alias the rest.
    std::vector<uint64_t> outcomes(count, 0);
    for (size_t i = 0; i < count; ++i) {
        outcomes[i] += entries[i].threshold;
        outcomes[entries[i].alias] += (uint64_t(1) << 32) - entries[i].threshold;
    }
    for (size_t i = 0; i < count; ++i)
        entries[i].probability = float(double(outcomes[i]) / (double(count) * SCALE));
    return entries;
}

}  // namespace vkpath::scene
