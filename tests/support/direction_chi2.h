// Chi-square goodness of fit for direction samplers, after Mitsuba 3's
// ChiSquareTest: directions are binned over (phi, cos theta) in a frame of
// the test's choosing, the sampler's own pdf is integrated over every cell,
// and Pearson's test compares the two (sparse cells pooled).
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "shared/sampling.h"
#include "support/statistics.h"

namespace vkpath::test {

struct DirectionGrid {
    int phiBins = 202;
    int cosBins = 101;  // odd: cos theta = 0 is the middle of a bin, not an edge
    shared::Frame frame = shared::makeFrame(glm::vec3(0, 0, 1));
    // Midpoint rule with an even number of points per cell axis, so a jump of
    // the pdf at the middle of a cell (the hemisphere boundary) integrates exactly.
    int pointsPerAxis = 8;
};

std::vector<double> binDirections(const DirectionGrid& grid, const std::vector<glm::vec3>& directions);

// Expected count per cell: sampleCount * integral of pdf over the cell.
std::vector<double> expectedCounts(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf,
                                   double sampleCount);

// The integral of pdf over the whole sphere of directions (should be 1).
double integrateOverSphere(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf);

ChiSquareResult chiSquareDirections(const DirectionGrid& grid, const std::vector<glm::vec3>& directions,
                                    const std::function<double(glm::vec3)>& pdf);

}  // namespace vkpath::test
