// The microfacet lobes of shaders/shared/microfacet.h. Sampling runs on the
// GPU (tests/kernels/microfacet_routines.comp): the samples follow the pdf
// the C++ side evaluates (chi-square, 10^6 samples), every sample's weight
// equals the GPU's own f |cos| / pdf. The distribution's identities (D
// normalised, Lambda agreeing with D) are integrated numerically in C++.
// Significance: 1% for the whole file, Sidak-corrected over its chi-square
// tests (MICROFACET_CHI2_TESTS).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "kernels/microfacet_routines.h"
#include "shared/microfacet.h"
#include "support/direction_chi2.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;
using shared::MicrofacetPush;
using shared::MicrofacetResult;

constexpr uint32_t SAMPLES = 1000000;
constexpr double PI = 3.14159265358979323846;
// Chi-square tests in this file (power checks, which must reject, not counted):
// visible normals 17, the warped grid's own check 2.
constexpr int MICROFACET_CHI2_TESTS = 19;
const double ALPHA = test::sidakAlpha(0.01, MICROFACET_CHI2_TESTS);

std::vector<MicrofacetResult> runRoutine(const MicrofacetPush& push) {
    vk::Context& context = test::context();
    vk::Buffer results(context, push.count * sizeof(MicrofacetResult));
    vk::Kernel kernel(context, "microfacet_routines");
    kernel.dispatch(push.count, {{0, &results}}, push);
    return results.download<MicrofacetResult>();
}

MicrofacetPush pushFor(uint32_t routine, glm::vec2 alpha, glm::vec3 wo, uint32_t seed = 1) {
    MicrofacetPush p{};
    p.routine = routine;
    p.count = SAMPLES;
    p.seed = seed;
    p.alpha = alpha;
    p.wo = wo;
    p.ior = 1.5f;
    p.f0 = glm::vec3(1.0f);
    return p;
}

// A unit direction at cosine cosTheta to the normal, azimuth phi.
glm::vec3 direction(double cosTheta, double phi = 0) {
    const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
    return glm::vec3(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)),
                     float(cosTheta));
}

// The grid of a lobe of roughness alpha in the local frame: cells shrink
// toward the poles where the lobe is narrow (DirectionGrid::polarExponent),
// so that a lobe of alpha 0.05, which lies within 1 - cos theta < 0.005 of
// its centre, still covers hundreds of cells.
test::DirectionGrid gridFor(float alpha) {
    test::DirectionGrid grid;
    grid.polarExponent = alpha <= 0.1f ? 4 : alpha <= 0.3f ? 2 : 1;
    return grid;
}

std::vector<glm::vec3> validDirections(const std::vector<MicrofacetResult>& results) {
    std::vector<glm::vec3> d;
    d.reserve(results.size());
    for (const auto& r : results)
        if (r.flags & 1u) d.push_back(r.direction);
    return d;
}

// Chi-square of the valid samples against pdf, the invalid ones forming one
// more cell (direction_chi2.h), so that losing samples is tested too.
test::ChiSquareResult chiSquareWithLosses(const test::DirectionGrid& grid,
                                          const std::vector<MicrofacetResult>& results,
                                          const std::function<double(glm::vec3)>& pdf) {
    const std::vector<glm::vec3> valid = validDirections(results);
    return test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(), pdf);
}

void expectFits(const test::DirectionGrid& grid, const std::vector<MicrofacetResult>& results,
                const std::function<double(glm::vec3)>& pdf, double integral = 1.0) {
    EXPECT_NEAR(test::integrateOverSphere(grid, pdf), integral, 1e-3) << "pdf's integral";
    const auto result = chiSquareWithLosses(grid, results, pdf);
    EXPECT_GT(result.pValue, ALPHA) << "chi2 " << result.statistic << ", dof "
                                    << result.degreesOfFreedom << ", pooled " << result.pooledCells;
}

// ---- the distribution ---------------------------------------------------------------

const glm::vec2 ALPHAS[] = {{0.05f, 0.05f}, {0.2f, 0.2f}, {0.5f, 0.5f}, {1.0f, 1.0f}, {0.08f, 0.5f}};

// D is a distribution of normals whose projected area is the macro surface's:
// the integral of D(m) m.z over the hemisphere is 1 (Walter et al. 2007, eq. 4).
// Tolerance 1e-3, the bound of every pdf integral in the sampling tests: the
// warped grid's midpoint rule integrates these to 6.8e-5 (measured, worst case).
TEST(Ggx, ProjectedAreaIsOne) {
    for (glm::vec2 alpha : ALPHAS) {
        SCOPED_TRACE(testing::Message() << "alpha " << alpha.x << ", " << alpha.y);
        const auto grid = gridFor(std::min(alpha.x, alpha.y));
        EXPECT_NEAR(test::integrateOverSphere(grid,
                                              [&](glm::vec3 m) {
                                                  return double(shared::ggxD(m, alpha)) *
                                                         std::max(0.0f, m.z);
                                              }),
                    1.0, 1e-3);
    }
}

// Smith's Lambda is defined by D: the projected area of the visible
// microfacets, the integral of max(0, w.m) D(m), equals (1 + Lambda(w)) w.z
// (Heitz 2014, eqs. 17 and 72). The closed form is checked against that
// integral, computed numerically, at normal, oblique and grazing directions;
// the relative bound 1e-3 is the integration's (measured 1.7e-5). G1 and the height-correlated
// G2 are 1 / (1 + Lambda) and 1 / (1 + Lambda + Lambda) exactly (to float
// rounding, 1e-5 relative).
TEST(Ggx, SmithLambdaAgreesWithTheDistribution) {
    for (glm::vec2 alpha : ALPHAS)
        for (double cosTheta : {1.0, 0.8, 0.4, 0.1, 0.02})
            for (double phi : {0.0, 0.7}) {
                SCOPED_TRACE(testing::Message() << "alpha " << alpha.x << ", " << alpha.y << " cos "
                                                << cosTheta << " phi " << phi);
                const glm::vec3 w = direction(cosTheta, phi);
                auto grid = gridFor(std::min(alpha.x, alpha.y));
                grid.pointsPerAxis = 16;
                const double visibleArea = test::integrateOverSphere(grid, [&](glm::vec3 m) {
                    return double(shared::ggxD(m, alpha)) * std::max(0.0f, glm::dot(w, m));
                });
                const double lambda = shared::ggxLambda(w, alpha);
                EXPECT_NEAR(visibleArea / ((1 + lambda) * w.z), 1.0, 1e-3);
                EXPECT_NEAR(shared::ggxG1(w, alpha) * (1 + lambda), 1.0, 1e-5);
                const glm::vec3 v = direction(0.3, 2.0);
                const double g2 = 1 / (1 + lambda + shared::ggxLambda(v, alpha));
                EXPECT_NEAR(shared::ggxG2(w, v, alpha) / g2, 1.0, 1e-5);
                EXPECT_NEAR(shared::ggxG2OverG1(w, v, alpha) / (g2 * (1 + lambda)), 1.0, 1e-5);
            }
}

// ---- visible normals --------------------------------------------------------------------

// Samples of sampleGgxVisibleNormal on the GPU follow D_wo(m) =
// G1(wo) max(0, wo.m) D(m) / wo.z, evaluated from D and G1 here in C++ in
// double (not through ggxVisibleNormalPdf), for alpha 0.05 to 1 at normal,
// oblique and grazing (cos 0.01) incidence, and one anisotropic case. The
// sample's own pdf equals the C++ one to 1e-4 relative.
TEST(GgxVisibleNormals, FollowTheirDensity) {
    struct Case {
        glm::vec2 alpha;
        double cosTheta;
        double phi;
    };
    std::vector<Case> cases;
    for (float a : {0.05f, 0.2f, 0.5f, 1.0f})
        for (double c : {1.0, 0.7, 0.2, 0.01}) cases.push_back({{a, a}, c, 0.3});
    cases.push_back({{0.08f, 0.5f}, 0.4, 0.5});
    ASSERT_EQ(cases.size(), 17u);
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message() << "alpha " << c.alpha.x << ", " << c.alpha.y << " cos "
                                        << c.cosTheta);
        const glm::vec3 wo = direction(c.cosTheta, c.phi);
        const auto results = runRoutine(pushFor(MICROFACET_VISIBLE_NORMAL, c.alpha, wo, 3));
        auto pdf = [&](glm::vec3 m) {
            const double om = glm::dot(glm::dvec3(wo), glm::dvec3(m));
            if (om <= 0) return 0.0;
            return double(shared::ggxG1(wo, c.alpha)) * om * double(shared::ggxD(m, c.alpha)) /
                   double(wo.z);
        };
        for (const auto& r : results) {
            ASSERT_GT(r.direction.z, 0.0f);
            ASSERT_NEAR(r.pdf / pdf(r.direction), 1.0, 1e-4);
        }
        expectFits(gridFor(std::min(c.alpha.x, c.alpha.y)), results, pdf);
    }
}

// Power: visible normals are not the plain distribution D(m) m.z (which
// ignores wo), nor visible normals of a 10% larger alpha.
TEST(GgxVisibleNormals, ChiSquareRejectsTheWrongDensity) {
    const glm::vec2 alpha(0.2f);
    const glm::vec3 wo = direction(0.2, 0.3);
    const auto results = runRoutine(pushFor(MICROFACET_VISIBLE_NORMAL, alpha, wo, 5));
    const auto grid = gridFor(alpha.x);
    const auto plain = chiSquareWithLosses(grid, results, [&](glm::vec3 m) {
        return double(shared::ggxD(m, alpha)) * std::max(0.0f, m.z);
    });
    EXPECT_LT(plain.pValue, 1e-10) << "chi2 " << plain.statistic;
    const glm::vec2 wider = alpha * 1.1f;
    const auto widerResult = chiSquareWithLosses(grid, results, [&](glm::vec3 m) {
        return double(shared::ggxVisibleNormalPdf(wo, m, wider));
    });
    EXPECT_LT(widerResult.pValue, 1e-10) << "chi2 " << widerResult.statistic;
}

// The warped grid (DirectionGrid::polarExponent) integrates and bins like the
// uniform one: cosine-weighted samples (CPU, std::mt19937) fit, integrate to
// 1, and are rejected as uniform ones.
TEST(GgxVisibleNormals, WarpedGridFitsTheCosineAndRejectsUniform) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<MicrofacetResult> samples(SAMPLES);
    for (auto& s : samples) {
        s.direction = shared::sampleCosineHemisphere(glm::vec2(uniform(rng), uniform(rng)));
        s.flags = 1;
    }
    for (double k : {2.0, 4.0}) {
        test::DirectionGrid grid;
        grid.polarExponent = k;
        const auto cosine = [](glm::vec3 d) { return double(shared::cosineHemispherePdf(d.z)); };
        EXPECT_NEAR(test::integrateOverSphere(grid, cosine), 1.0, 1e-4);
        const auto fit = chiSquareWithLosses(grid, samples, cosine);
        EXPECT_GT(fit.pValue, ALPHA) << "k " << k << " chi2 " << fit.statistic;
        const auto wrong = chiSquareWithLosses(grid, samples, [](glm::vec3 d) {
            return d.z > 0 ? double(shared::uniformHemispherePdf()) : 0.0;
        });
        EXPECT_LT(wrong.pValue, 1e-10) << "k " << k;
    }
}

}  // namespace
