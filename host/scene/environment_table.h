// The environment map's importance-sampling table (see
// shaders/shared/environment_sampling.h for the method and why).
#pragma once

#include <vector>

#include "image/image.h"
#include "shared/environment_sampling.h"

namespace vkpath::scene {

struct EnvironmentTable {
    std::vector<shared::EnvAliasEntry> entries;  // one per texel; empty when the map is black
    double totalWeight = 0;                      // sum of luminance x sin(theta) over texels
};

// Rec. 709 luminance of linear RGB.
double luminance(const glm::vec3& rgb);

// Builds the alias table for weights luminance(texel) x sin(theta at the
// texel's centre), in double; every texel with weight > 0 keeps a nonzero
// probability. Each entry's probability is computed from the quantised
// thresholds exactly (64-bit integer sums), so sampling and pdf agree.
EnvironmentTable buildEnvironmentTable(const image::Image& map);

}  // namespace vkpath::scene
