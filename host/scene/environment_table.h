// The environment map's importance-sampling table (see
// shaders/shared/environment_sampling.h for the method and why).
#pragma once

#include <vector>

#include "image/image.h"
#include "shared/alias.h"

namespace vkpath::scene {

struct EnvironmentTable {
    std::vector<shared::AliasEntry> entries;  // one per texel; empty when the map is black
    double totalWeight = 0;                      // sum of luminance x sin(theta) over texels
};

// Rec. 709 luminance of linear RGB.
double luminance(const glm::vec3& rgb);

// The alias table (scene/alias_table.h) for weights luminance(texel) x
// sin(theta at the texel's centre).
EnvironmentTable buildEnvironmentTable(const image::Image& map);

}  // namespace vkpath::scene
