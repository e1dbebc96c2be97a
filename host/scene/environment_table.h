// The environment map's importance-sampling table (see
// shaders/shared/environment_sampling.h for the method and why).
#pragma once

#include <vector>

#include "image/image.h"
#include "shared/alias.h"

namespace vkpath::scene {

struct EnvironmentTable {
    std::vector<shared::AliasEntry> entries;  // one per texel's cell; empty when the map is black
    // The sum of the cells' weights: the integral over the map's (u, v) square of
    // the bilinear luminance x sin(theta). The integral of luminance over the
    // sphere is 2 pi^2 totalWeight (d omega = 2 pi^2 sin(theta) du dv).
    double totalWeight = 0;
};

// Rec. 709 luminance of linear RGB.
double luminance(const glm::vec3& rgb);

// How one row's cell in v, [j/H, (j+1)/H), weighs the bilinear interpolation
// between rows: the integrals over it of sin(pi v) times the weight of the row
// above (previous), of the row itself (self) and of the row below (next).
// They sum to the integral of sin(pi v) over the cell.
struct RowWeights {
    double previous = 0, self = 0, next = 0;
};
RowWeights bilinearRowWeights(uint32_t row, uint32_t height);

// The alias table (scene/alias_table.h) over the texels' cells, each weighted
// by the integral over it of the bilinearly interpolated luminance (the
// radiance environmentRadiance returns) times sin(theta), in closed form.
// Why the integral: the bilinear radiance is positive in the cell of a black
// texel next to a bright one, where a weight from the texel's own value
// would be 0 and light sampling would never go; the integral is positive
// exactly where the radiance can be (but on a set of measure zero), and
// it is the cell's share of the integrand's mass, so the piecewise-constant
// pdf is the cell average of luminance x sin(theta) and the estimator's
// weight L / pdf stays within a few times its mean. (The maximum over the
// cell would be positive in the same cells but would oversample them: a black
// texel beside a sun would get half the sun's weight for an eighth of its
// energy.)
EnvironmentTable buildEnvironmentTable(const image::Image& map);

}  // namespace vkpath::scene
