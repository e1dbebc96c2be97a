// Building the light tree (shaders/shared/light_tree.h) over the bounded
// lights of a scene, in double, on the host.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "shared/light_tree.h"
#include "shared/lights.h"
#include "shared/scene_data.h"

namespace vkpath::wavefront {

struct LightTree {
    // Depth-first: an interior node's first child follows it. Empty: no tree.
    std::vector<shared::LightTreeNode> nodes;
    // Per light of the tree's range, its path from the root (bit i: the
    // second child at depth i); VKP_NO_LIGHT for a light of no power, which
    // the tree leaves out.
    std::vector<uint32_t> trails;
    uint32_t depth = 0;  // of the deepest leaf
};

// The tree over `lights` (every one bounded: not VKP_LIGHT_IS_INFINITE),
// with the weights `power` (the alias table's). Split where the cost of
// Conty Estevez and Kulla (HPG 2018, section 4.4: power times the measure
// of the emission's directions times the box's surface area, with its
// aspect ratio) is least among 12 bins of the centroids on each axis, by
// count below a depth that could pass VKP_LIGHT_TREE_MAX_DEPTH. Empty when
// fewer than two lights have power.
LightTree buildLightTree(std::span<const shared::Light> lights, std::span<const double> power);

}  // namespace vkpath::wavefront
