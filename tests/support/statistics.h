// Statistical tools for tests: chi-square goodness of fit, with pooling of
// sparse cells, and the Sidak correction for many tests.
#pragma once

#include <cstddef>
#include <vector>

#include "image/statistics.h"

namespace vkpath::test {

// The chi-square distribution's upper tail P(X > statistic) for
// degreesOfFreedom > 0 (Boost.Math: Q(k/2, x/2), the regularised incomplete
// gamma function's upper part).
double chiSquarePValue(double statistic, int degreesOfFreedom);

struct ChiSquareResult {
    double statistic = 0;
    int degreesOfFreedom = 0;
    double pValue = 1;
    size_t pooledCells = 0;  // cells merged because their expected count was below the minimum
};

// Pearson's chi-square test of observed counts against expected counts (same
// total). Cells with expected count < minExpected are pooled into one cell,
// as Mitsuba 3's ChiSquareTest does. Any observation in a cell whose expected
// count is exactly zero fails outright (p = 0).
ChiSquareResult chiSquareTest(const std::vector<double>& observed,
                              const std::vector<double>& expected, double minExpected = 5.0);

// Sidak's per-test significance: image::sidakAlpha (host/image/statistics.h).
using image::sidakAlpha;

}  // namespace vkpath::test
