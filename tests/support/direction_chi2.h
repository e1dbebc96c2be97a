// Chi-square goodness of fit for direction samplers, after Mitsuba 3's
// ChiSquareTest: directions are binned over (phi, cos theta) in a frame of
// the test's choosing, the sampler's own pdf is integrated over every cell,
// and Pearson's test compares the two (sparse cells pooled).
#pragma once

#include <functional>
#include <glm/glm.hpp>
#include <vector>

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
    // Cells uniform in y in [-1, 1] with cos theta = sign(y) (1 - (1 - |y|)^k):
    // k = 1 is uniform in cos theta; k > 1 shrinks the cells toward both poles
    // (1 - |cos theta| = (1 - |y|)^k), so a lobe much narrower than a cos-theta
    // cell (a GGX lobe of alpha 0.05 lies within 1 - cos theta < 0.005 of its
    // pole) still spreads over many cells. y = 0 stays the middle of a cell.
    double polarExponent = 1;
};

std::vector<double> binDirections(const DirectionGrid& grid,
                                  const std::vector<glm::vec3>& directions);

// Expected count per cell: sampleCount * integral of pdf over the cell.
std::vector<double> expectedCounts(const DirectionGrid& grid,
                                   const std::function<double(glm::vec3)>& pdf, double sampleCount);

// The integral of pdf over the whole sphere of directions (should be 1).
double integrateOverSphere(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf);

ChiSquareResult chiSquareDirections(const DirectionGrid& grid,
                                    const std::vector<glm::vec3>& directions,
                                    const std::function<double(glm::vec3)>& pdf);

// The same for a sampler that may fail (a BSDF sample reflected below the
// surface): `directions` are its successful samples, `lostSamples` the failed
// ones, and pdf the density of the successful ones, whose integral is then
// below 1. The failures form one more cell, expected N (1 - integral of pdf).
ChiSquareResult chiSquareDirectionsWithLosses(const DirectionGrid& grid,
                                              const std::vector<glm::vec3>& directions,
                                              size_t lostSamples,
                                              const std::function<double(glm::vec3)>& pdf);

}  // namespace vkpath::test
