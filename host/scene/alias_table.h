// Building alias tables (shaders/shared/alias.h) on the host, in double.
#pragma once

#include <span>
#include <vector>

#include "shared/alias.h"

namespace vkpath::scene {

// One entry per weight; empty when no weight is positive. Negative and
// non-finite weights count as zero. Every element with a positive weight
// keeps a nonzero probability, and each entry's probability is computed
// exactly (64-bit integer sums) from the quantised 32-bit thresholds.
std::vector<shared::AliasEntry> buildAliasTable(std::span<const double> weights);

}  // namespace vkpath::scene
