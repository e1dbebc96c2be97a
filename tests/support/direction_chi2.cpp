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

template <typename F>
void forEachCellIntegral(const DirectionGrid& grid, const std::function<double(glm::vec3)>& pdf, F&& visit) {
    const double dPhi = 2 * PI / grid.phiBins, dCos = 2.0 / grid.cosBins;
    const int k = grid.pointsPerAxis;
    for (int c = 0; c < grid.cosBins; ++c)
        for (int p = 0; p < grid.phiBins; ++p) {
            double sum = 0;
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k; ++j) {
                    const double cosTheta = -1 + (c + (i + 0.5) / k) * dCos;
                    const double phi = (p + (j + 0.5) / k) * dPhi;
                    const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
                    const glm::vec3 local(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)),
                                          float(cosTheta));
                    sum += pdf(shared::frameToWorld(grid.frame, local));
                }
            // d omega = d phi d cos theta.
            visit(c * grid.phiBins + p, sum / (k * k) * dPhi * dCos);
        }
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
    return chiSquareTest(binDirections(grid, directions), expectedCounts(grid, pdf, double(directions.size())));
}

}  // namespace vkpath::test
