#include "support/statistics.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace vkpath::test {

double regularizedGammaQ(double a, double x) {
    if (x < 0 || a <= 0) throw std::invalid_argument("regularizedGammaQ: bad arguments");
    if (x == 0) return 1.0;
    const double logPrefix = a * std::log(x) - x - std::lgamma(a);
    constexpr double EPS = 1e-15;
    if (x < a + 1) {
        // P(a, x) by its series; Q = 1 - P.
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * EPS) break;
        }
        return 1.0 - sum * std::exp(logPrefix);
    }
    // Q(a, x) by its continued fraction, modified Lentz.
    constexpr double TINY = std::numeric_limits<double>::min() / EPS;
    double b = x + 1 - a, c = 1 / TINY, d = 1 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < TINY) d = TINY;
        c = b + an / c;
        if (std::abs(c) < TINY) c = TINY;
        d = 1 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1) < EPS) break;
    }
    return std::exp(logPrefix) * h;
}

ChiSquareResult chiSquareTest(const std::vector<double>& observed, const std::vector<double>& expected,
                              double minExpected) {
    if (observed.size() != expected.size()) throw std::invalid_argument("chiSquareTest: size mismatch");
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
    r.pValue = r.degreesOfFreedom > 0 ? regularizedGammaQ(0.5 * r.degreesOfFreedom, 0.5 * r.statistic) : 1.0;
    return r;
}


}  // namespace vkpath::test
