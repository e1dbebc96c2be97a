#include "support/direction_chi2.h"

#include <algorithm>
#include <cmath>

namespace vkpath::test {
namespace {

constexpr double PI = 3.14159265358979323846;

// The polar cell coordinate y of cos theta and back (DirectionGrid::polarExponent).
double polarCoordinate(const DirectionGrid& grid, double cosTheta) {
    const double y = 1 - std::pow(1 - std::abs(cosTheta), 1 / grid.polarExponent);
    return std::copysign(y, cosTheta);
}

double cosineOfPolarCoordinate(const DirectionGrid& grid, double y) {
    return std::copysign(1 - std::pow(1 - std::abs(y), grid.polarExponent), y);
}

int cellOf(const DirectionGrid& grid, glm::vec3 worldDirection) {
    const glm::vec3 d = shared::frameToLocal(grid.frame, worldDirection);
    double phi = std::atan2(double(d.y), double(d.x));
    if (phi < 0) phi += 2 * PI;
    const double cosTheta = std::clamp(double(d.z), -1.0, 1.0);
    const int p = std::min(grid.phiBins - 1, int(phi / (2 * PI) * grid.phiBins));
    const double y = grid.polarExponent == 1 ? cosTheta : polarCoordinate(grid, cosTheta);
    const int c = std::min(grid.cosBins - 1, int((y + 1) / 2 * grid.cosBins));
    return c * grid.phiBins + p;
}

// The integral of pdf over cell (c, p) by the midpoint rule, k x k points.
double cellIntegral(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf, int c,
                    int p, int k) {
    const double dPhi = 2 * PI / grid.phiBins, dCos = 2.0 / grid.cosBins;
    auto at = [&](double cosTheta, int j) {
        const double phi = (p + (j + 0.5) / k) * dPhi;
        const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
        const glm::vec3 local(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)),
                              float(cosTheta));
        return pdf(shared::frameToWorld(grid.frame, local));
    };
    double sum = 0;
    if (grid.polarExponent == 1) {
        for (int i = 0; i < k; ++i)
            for (int j = 0; j < k; ++j) sum += at(-1 + (c + (i + 0.5) / k) * dCos, j);
        // d omega = d phi d cos theta.
        return sum / (k * k) * dPhi * dCos;
    }
    // Warped cells: the midpoint in y of each of the k sub-intervals, weighted
    // by the sub-interval's exact extent in cos theta (so a constant pdf
    // integrates exactly, as in the uniform grid).
    for (int i = 0; i < k; ++i) {
        const double y0 = -1 + (c + double(i) / k) * dCos, y1 = -1 + (c + (i + 1.0) / k) * dCos;
        const double cosExtent =
            cosineOfPolarCoordinate(grid, y1) - cosineOfPolarCoordinate(grid, y0);
        const double cosMid = cosineOfPolarCoordinate(grid, 0.5 * (y0 + y1));
        for (int j = 0; j < k; ++j) sum += at(cosMid, j) * cosExtent;
    }
    return sum / k * dPhi;
}

template <typename F>
void forEachCellIntegral(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf,
                         F&& visit) {
    for (int c = 0; c < grid.cosBins; ++c)
        for (int p = 0; p < grid.phiBins; ++p)
            visit(c * grid.phiBins + p, cellIntegral(grid, pdf, c, p, grid.pointsPerAxis));
}

}  // namespace

std::vector<double> binDirections(const DirectionGrid& grid,
                                  const std::vector<glm::vec3>& directions) {
    std::vector<double> counts(size_t(grid.phiBins) * grid.cosBins, 0);
    for (const glm::vec3& d : directions) counts[cellOf(grid, d)] += 1;
    return counts;
}

std::vector<double> expectedCounts(const DirectionGrid& grid,
                                   const std::function<double(glm::vec3)>& pdf,
                                   double sampleCount) {
    std::vector<double> expected(size_t(grid.phiBins) * grid.cosBins, 0);
    forEachCellIntegral(
        grid, pdf, [&](int cell, double integral) { expected[cell] = integral * sampleCount; });
    return expected;
}

double integrateOverSphere(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf) {
    double total = 0;
    forEachCellIntegral(grid, pdf, [&](int, double integral) { total += integral; });
    return total;
}

namespace {

// Expected counts of sampleCount samples, with the cells that hold samples
// but whose midpoints all miss the pdf's support integrated again finer.
std::vector<double> expectedForObserved(const DirectionGrid& grid,
                                        const std::vector<double>& observed,
                                        const std::function<double(glm::vec3)>& pdf,
                                        double sampleCount) {
    std::vector<double> expected = expectedCounts(grid, pdf, sampleCount);
    // A cell the pdf's support only grazes (a light's corner) may hold none of
    // the midpoints: before its samples count as samples where the pdf is 0,
    // it is integrated again with 32 times as many points per axis.
    for (int cell = 0; cell < int(observed.size()); ++cell)
        if (observed[cell] > 0 && expected[cell] == 0)
            expected[cell] = cellIntegral(grid, pdf, cell / grid.phiBins, cell % grid.phiBins,
                                          32 * grid.pointsPerAxis) *
                             sampleCount;
    return expected;
}

}  // namespace

ChiSquareResult chiSquareDirections(const DirectionGrid& grid,
                                    const std::vector<glm::vec3>& directions,
                                    const std::function<double(glm::vec3)>& pdf) {
    const std::vector<double> observed = binDirections(grid, directions);
    return chiSquareTest(observed,
                         expectedForObserved(grid, observed, pdf, double(directions.size())));
}

ChiSquareResult chiSquareDirectionsWithLosses(const DirectionGrid& grid,
                                              const std::vector<glm::vec3>& directions,
                                              size_t lostSamples,
                                              const std::function<double(glm::vec3)>& pdf) {
    const double n = double(directions.size() + lostSamples);
    std::vector<double> observed = binDirections(grid, directions);
    std::vector<double> expected = expectedForObserved(grid, observed, pdf, n);
    double total = 0;
    for (double e : expected) total += e;
    observed.push_back(double(lostSamples));
    expected.push_back(std::max(0.0, n - total));
    return chiSquareTest(observed, expected);
}

}  // namespace vkpath::test
