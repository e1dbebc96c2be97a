#include "support/statistics.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vkpath::test {

double chiSquarePValue(double statistic, int degreesOfFreedom) {
    if (degreesOfFreedom <= 0 || !(statistic >= 0))
        throw std::invalid_argument("chiSquarePValue: bad arguments");
    if (std::isinf(statistic)) return 0.0;
    return boost::math::cdf(boost::math::complement(
        boost::math::chi_squared_distribution<double>(degreesOfFreedom), statistic));
}

ChiSquareResult chiSquareTest(const std::vector<double>& observed,
                              const std::vector<double>& expected, double minExpected) {
    if (observed.size() != expected.size())
        throw std::invalid_argument("chiSquareTest: size mismatch");
    ChiSquareResult r;
    double pooledObserved = 0, pooledExpected = 0;
    int cells = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] == 0 && observed[i] > 0) {
            // A sample where the density is zero: the routine is wrong.
            r.statistic = std::numeric_limits<double>::infinity();
            r.pValue = 0;
            return r;
        }
        if (expected[i] < minExpected) {
            pooledObserved += observed[i];
            pooledExpected += expected[i];
            ++r.pooledCells;
            continue;
        }
        const double diff = observed[i] - expected[i];
        r.statistic += diff * diff / expected[i];
        ++cells;
    }
    if (pooledExpected > 0) {
        const double diff = pooledObserved - pooledExpected;
        r.statistic += diff * diff / pooledExpected;
        ++cells;
    }
    r.degreesOfFreedom = cells - 1;
    r.pValue = r.degreesOfFreedom > 0 ? chiSquarePValue(r.statistic, r.degreesOfFreedom) : 1.0;
    return r;
}
}  // namespace vkpath::test
