#include "support/direction_chi2.h"

#include <algorithm>
#include <cmath>

namespace vkpath::test {
namespace {

constexpr double PI = 3.14159265358979323846;

int cellOf(const DirectionGrid& grid, glm::vec3 worldDirection) {
    const glm::vec3 d = shared::frameToLocal(grid.frame, worldDirection);
    double phi = std::atan2(double(d.y), double(d.x));
    if (phi < 0) phi += 2 * PI;
    const double cosTheta = std::clamp(double(d.z), -1.0, 1.0);
    const int p = std::min(grid.phiBins - 1, int(phi / (2 * PI) * grid.phiBins));
    const int c = std::min(grid.cosBins - 1, int((cosTheta + 1) / 2 * grid.cosBins));
    return c * grid.phiBins + p;
}

// The integral of pdf over cell (c, p) by the midpoint rule, k x k points.
double cellIntegral(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf, int c, int p, int k) {
    const double dPhi = 2 * PI / grid.phiBins, dCos = 2.0 / grid.cosBins;
    double sum = 0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            const double cosTheta = -1 + (c + (i + 0.5) / k) * dCos;
            const double phi = (p + (j + 0.5) / k) * dPhi;
            const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
            const glm::vec3 local(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)), float(cosTheta));
            sum += pdf(shared::frameToWorld(grid.frame, local));
        }
    // d omega = d phi d cos theta.
    return sum / (k * k) * dPhi * dCos;
}

template <typename F>
void forEachCellIntegral(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf, F&& visit) {
    for (int c = 0; c < grid.cosBins; ++c)
        for (int p = 0; p < grid.phiBins; ++p)
            visit(c * grid.phiBins + p, cellIntegral(grid, pdf, c, p, grid.pointsPerAxis));
}

}  // namespace

std::vector<double> binDirections(const DirectionGrid& grid, const std::vector<glm::vec3>& directions) {
    std::vector<double> counts(size_t(grid.phiBins) * grid.cosBins, 0);
    for (const glm::vec3& d : directions) counts[cellOf(grid, d)] += 1;
    return counts;
}

std::vector<double> expectedCounts(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf,
                                   double sampleCount) {
    std::vector<double> expected(size_t(grid.phiBins) * grid.cosBins, 0);
    forEachCellIntegral(grid, pdf, [&](int cell, double integral) { expected[cell] = integral * sampleCount; });
    return expected;
}

double integrateOverSphere(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf) {
    double total = 0;
    forEachCellIntegral(grid, pdf, [&](int, double integral) { total += integral; });
    return total;
}

ChiSquareResult chiSquareDirections(const DirectionGrid& grid, const std::vector<glm::vec3>& directions,
                                    const std::function<double(glm::vec3)>& pdf) {
    const std::vector<double> observed = binDirections(grid, directions);
    std::vector<double> expected = expectedCounts(grid, pdf, double(directions.size()));
    // A cell the pdf's support only grazes (a light's corner) may hold none of
    // the midpoints: before its samples count as samples where the pdf is 0,
    // it is integrated again with 32 times as many points per axis.
    for (int cell = 0; cell < int(observed.size()); ++cell)
        if (observed[cell] > 0 && expected[cell] == 0)
            expected[cell] = cellIntegral(grid, pdf, cell / grid.phiBins, cell % grid.phiBins,
                                          32 * grid.pointsPerAxis) *
                             double(directions.size());
    return chiSquareTest(observed, expected);
}

}  // namespace vkpath::test
