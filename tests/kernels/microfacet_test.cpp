// The microfacet lobes of shaders/shared/microfacet.h. Sampling runs on the
// GPU (tests/kernels/microfacet_routines.comp): the samples follow the pdf
// the C++ side evaluates (chi-square, 10^6 samples), every sample's weight
// equals the GPU's own f |cos| / pdf. The distribution's identities (D
// normalised, Lambda agreeing with D) are integrated numerically in C++.
// Significance: 1% for the whole file, Sidak-corrected over its chi-square
// tests (MICROFACET_CHI2_TESTS).
#include "shared/microfacet.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <random>
#include <vector>

#include "image/statistics.h"
#include "kernels/microfacet_routines.h"
#include "shared/rng.h"
#include "support/direction_chi2.h"
#include "support/fresnel_rounding.h"
#include "support/test_context.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;
using shared::MicrofacetPush;
using shared::MicrofacetResult;

constexpr uint32_t SAMPLES = 1000000;
constexpr double PI = 3.14159265358979323846;
// Statistical tests in this file (power checks, which must reject, not counted):
// chi-square of visible normals 17, of the warped grid's own check 2, of the
// conductor 14, of the dielectric 9; binomial z-tests of the conductor's limit
// alpha -> 0: 3.
constexpr int MICROFACET_STATISTICAL_TESTS = 45;
const double ALPHA = test::sidakAlpha(0.01, MICROFACET_STATISTICAL_TESTS);
const double Z_CRITICAL = image::normalCritical(ALPHA);

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

// The grid of a narrow lobe reflected or refracted near the horizon, where
// the warped cells are widest: uniform in cos theta, 32 x 32 points per cell
// (with 8 x 8, alpha 0.05 at cos theta_o 0.02 integrates 2.2% high; 32 and
// 64 agree to 1e-6).
test::DirectionGrid gridFor(float alpha, double cosTheta) {
    if (std::abs(cosTheta) >= 0.2 || alpha > 0.3f) return gridFor(alpha);
    test::DirectionGrid grid;
    grid.pointsPerAxis = 32;
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

// The samples fit pdf (chi-square, failures counted), and pdf integrates to 1
// (or, for a lobe that loses samples, to at most 1) within 1e-3.
void expectFits(const test::DirectionGrid& grid, const std::vector<MicrofacetResult>& results,
                const std::function<double(glm::vec3)>& pdf, bool losesSamples = false) {
    const double integral = test::integrateOverSphere(grid, pdf);
    if (losesSamples)
        EXPECT_LE(integral, 1.0 + 1e-3) << "pdf's integral";
    else
        EXPECT_NEAR(integral, 1.0, 1e-3) << "pdf's integral";
    const auto result = chiSquareWithLosses(grid, results, pdf);
    EXPECT_GT(result.pValue, ALPHA) << "chi2 " << result.statistic << ", dof "
                                    << result.degreesOfFreedom << ", pooled " << result.pooledCells;
}

// ---- the distribution ---------------------------------------------------------------

const glm::vec2 ALPHAS[] = {
    {0.05f, 0.05f}, {0.2f, 0.2f}, {0.5f, 0.5f}, {1.0f, 1.0f}, {0.08f, 0.5f}};

// D is a distribution of normals whose projected area is the macro surface's:
// the integral of D(m) m.z over the hemisphere is 1 (Walter et al. 2007).
// Tolerance 1e-3, the bound of every pdf integral in the sampling tests: the
// warped grid's midpoint rule integrates these to 6.8e-5 (measured, worst case).
TEST(Ggx, ProjectedAreaIsOne) {
    for (glm::vec2 alpha : ALPHAS) {
        SCOPED_TRACE(testing::Message() << "alpha " << alpha.x << ", " << alpha.y);
        const auto grid = gridFor(std::min(alpha.x, alpha.y));
        EXPECT_NEAR(
            test::integrateOverSphere(
                grid,
                [&](glm::vec3 m) { return double(shared::ggxD(m, alpha)) * std::max(0.0f, m.z); }),
            1.0, 1e-3);
    }
}

// Smith's Lambda is defined by D: the projected area of the visible
// microfacets, the integral of max(0, w.m) D(m), equals (1 + Lambda(w)) w.z
// (Heitz 2014). The closed form is checked against that
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
        SCOPED_TRACE(testing::Message()
                     << "alpha " << c.alpha.x << ", " << c.alpha.y << " cos " << c.cosTheta);
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

// ---- rough conductor -------------------------------------------------------------------

shared::Conductor conductorOf(const MicrofacetPush& p) {
    shared::Conductor c{};
    c.alpha = p.alpha;
    c.f0 = p.f0;
    c.eta = p.eta;
    c.k = p.k;
    c.fresnel = p.fresnel;
    return c;
}

// Gold's complex index at 650, 550 and 450 nm (Johnson and Christy 1972, as
// tabulated by refractiveindex.info), a coloured, strongly absorbing metal.
const glm::vec3 GOLD_ETA(0.166f, 0.433f, 1.467f);
const glm::vec3 GOLD_K(3.15f, 2.38f, 1.95f);

// The density of the conductor's wi written from D and G1 in double:
// D_wo(m) / (4 wo.m) with m the half vector (Walter et al. 2007, eq. 14),
// mirrored for a wo below the surface.
double conductorDensity(glm::vec3 wo, glm::vec3 wi, glm::vec2 alpha) {
    if (double(wo.z) * double(wi.z) <= 0) return 0;
    const double side = wo.z > 0 ? 1 : -1;
    const glm::dvec3 o = side * glm::dvec3(wo), i = side * glm::dvec3(wi);
    const glm::dvec3 m = glm::normalize(o + i);
    const double om = glm::dot(o, m);
    const double visible = double(shared::ggxG1(glm::vec3(o), alpha)) * om *
                           double(shared::ggxD(glm::vec3(m), alpha)) / o.z;
    return visible / (4 * om);
}

// Samples of the rough conductor follow their density, for alpha 0.05 to 1 at
// normal, oblique and grazing incidence, anisotropic, and from below (the
// conductor is two-sided). Samples reflected below the surface are lost:
// they form their own cell, expected N (1 - integral of the density).
TEST(RoughConductor, SamplesFollowTheirDensity) {
    struct Case {
        glm::vec2 alpha;
        double cosTheta;
    };
    std::vector<Case> cases;
    for (float a : {0.05f, 0.2f, 0.5f, 1.0f})
        for (double c : {1.0, 0.5, 0.05}) cases.push_back({{a, a}, c});
    cases.push_back({{0.3f, 0.05f}, 0.6});
    cases.push_back({{0.3f, 0.3f}, -0.6});
    ASSERT_EQ(cases.size(), 14u);
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message()
                     << "alpha " << c.alpha.x << ", " << c.alpha.y << " cos " << c.cosTheta);
        const glm::vec3 wo = direction(c.cosTheta, 0.4);
        const auto results = runRoutine(pushFor(MICROFACET_CONDUCTOR, c.alpha, wo, 7));
        auto pdf = [&](glm::vec3 wi) { return conductorDensity(wo, wi, c.alpha); };
        for (const auto& r : results)
            if (r.flags & 1u) {
                ASSERT_NEAR(r.pdf / pdf(r.direction), 1.0, 1e-3);
            }
        test::DirectionGrid grid = gridFor(std::min(c.alpha.x, c.alpha.y), c.cosTheta);
        grid.pointsPerAxis = 32;
        expectFits(grid, results, pdf, true);
    }
}

// Every sample's weight is f |cos| / pdf, evaluated on the GPU at the sampled
// direction (evalConductor, conductorPdf) and in C++ at the same direction,
// with Schlick's Fresnel of a coloured F0 and the complex Fresnel of gold,
// isotropic and anisotropic, from above and below, 10^6 samples each.
TEST(RoughConductor, WeightIsEvalOverPdf) {
    struct Case {
        glm::vec2 alpha;
        double cosTheta;
        uint32_t fresnel;
    };
    const Case cases[] = {
        {{0.05f, 0.05f}, 0.9, VKP_FRESNEL_SCHLICK}, {{0.5f, 0.5f}, 0.3, VKP_FRESNEL_COMPLEX},
        {{1.0f, 1.0f}, 0.02, VKP_FRESNEL_SCHLICK},  {{0.02f, 0.4f}, 0.7, VKP_FRESNEL_COMPLEX},
        {{0.3f, 0.3f}, -0.8, VKP_FRESNEL_COMPLEX},  {{0.3f, 0.3f}, 0.6, VKP_FRESNEL_CONSTANT}};
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message()
                     << "alpha " << c.alpha.x << ", " << c.alpha.y << " cos " << c.cosTheta);
        MicrofacetPush p = pushFor(MICROFACET_CONDUCTOR, c.alpha, direction(c.cosTheta, 1.1), 9);
        p.fresnel = c.fresnel;
        p.f0 = glm::vec3(0.95f, 0.64f, 0.54f);  // copper, glTF style
        p.eta = GOLD_ETA;
        p.k = GOLD_K;
        const shared::Conductor conductor = conductorOf(p);
        size_t valid = 0;
        for (const auto& r : runRoutine(p)) {
            if (!(r.flags & 1u)) continue;
            ++valid;
            ASSERT_EQ(r.flags, 1u);  // not delta
            ASSERT_NEAR(r.evalPdf / r.pdf, 1.0f, 1e-4f);
            const glm::vec3 f = shared::evalConductor(conductor, p.wo, r.direction);
            const float pdf = shared::conductorPdf(conductor, p.wo, r.direction);
            for (int k = 0; k < 3; ++k) {
                ASSERT_NEAR(r.eval[k] / r.evalPdf / r.weight[k], 1.0f, 1e-4f) << "GPU eval";
                ASSERT_NEAR(f[k] / pdf / r.weight[k], 1.0f, 1e-4f) << "C++ eval";
            }
        }
        EXPECT_GT(valid, SAMPLES / 2);
    }
}

// f(wo, wi) = f(wi, wo) (Helmholtz), f = eval / |cos wi|, for random pairs on
// either side, both Fresnel forms; to 1e-5 relative (float rounding: the two
// evaluations share m and differ only in the order of operations).
TEST(RoughConductor, Reciprocity) {
    std::mt19937 rng(21);
    std::normal_distribution<float> gauss;
    auto randomDirection = [&] {
        return glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
    };
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int compared = 0;
    for (int n = 0; n < 20000; ++n) {
        shared::Conductor c{};
        c.alpha = glm::vec2(0.02f + uniform(rng), 0.02f + uniform(rng));
        c.f0 = glm::vec3(0.95f, 0.64f, 0.54f);
        c.eta = GOLD_ETA;
        c.k = GOLD_K;
        c.fresnel = n % 3 == 0   ? VKP_FRESNEL_COMPLEX
                    : n % 3 == 1 ? VKP_FRESNEL_SCHLICK
                                 : VKP_FRESNEL_CONSTANT;
        glm::vec3 a = randomDirection(), b = randomDirection();
        if (std::abs(a.z) < 1e-3f || std::abs(b.z) < 1e-3f) continue;
        if (a.z * b.z < 0) b.z = -b.z;
        const glm::vec3 fab = shared::evalConductor(c, a, b) / std::abs(b.z);
        const glm::vec3 fba = shared::evalConductor(c, b, a) / std::abs(a.z);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(fab[k], fba[k], 1e-5f * fab[k]);
        ASSERT_GT(fab.x, 0.0f);
        ++compared;
    }
    EXPECT_GT(compared, 19000);
}

// The Fresnel equations with a complex index against their textbook form in
// double (Born and Wolf: r_s = (cos - w) / (cos + w), r_p = (n^2 cos - w) /
// (n^2 cos + w), w = sqrt(n^2 - sin^2)), an algebra independent of PBR's,
// to 2e-6 (float rounding of values <= 1); their limits: normal incidence
// ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2), grazing 1, k = 0 the dielectric's
// (including total internal reflection for n < 1). Schlick: F0 at normal
// incidence, 1 at grazing.
TEST(ConductorFresnel, ComplexIndexMatchesTheTextbookAndItsLimits) {
    const glm::vec2 metals[] = {{0.166f, 3.15f}, {1.467f, 1.95f}, {0.27f, 3.41f}, {1.2f, 7.26f},
                                {2.9f, 3.0f},    {1.5f, 0.0f},    {0.7f, 0.0f}};
    for (glm::vec2 nk : metals)
        for (double cosTheta : {1.0, 0.9, 0.6, 0.3, 0.1, 0.01, 0.0}) {
            SCOPED_TRACE(testing::Message()
                         << "n " << nk.x << " k " << nk.y << " cos " << cosTheta);
            const std::complex<double> n(nk.x, nk.y), n2 = n * n;
            const double sin2 = 1 - cosTheta * cosTheta;
            const std::complex<double> w = std::sqrt(n2 - sin2);
            const double rs = std::norm((cosTheta - w) / (cosTheta + w));
            const double rp = std::norm((n2 * cosTheta - w) / (n2 * cosTheta + w));
            const float f = shared::fresnelComplex(float(cosTheta), nk.x, nk.y);
            EXPECT_NEAR(f, 0.5 * (rs + rp), 2e-6);
            if (nk.y == 0) {
                EXPECT_NEAR(f, shared::fresnelDielectric(float(cosTheta), nk.x), 2e-6);
            }
        }
    for (glm::vec2 nk : metals) {
        const double n = nk.x, k = nk.y;
        EXPECT_NEAR(shared::fresnelComplex(1.0f, nk.x, nk.y),
                    ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), 1e-6);
        EXPECT_NEAR(shared::fresnelComplex(0.0f, nk.x, nk.y), 1.0, 1e-6);
    }
    const glm::vec3 f0(0.95f, 0.64f, 0.54f);
    EXPECT_EQ(shared::fresnelSchlick(f0, 1.0f), f0);
    EXPECT_EQ(shared::fresnelSchlick(f0, 0.0f), glm::vec3(1.0f));
    EXPECT_NEAR(shared::fresnelSchlick(f0, 0.5f).y, 0.64f + 0.36f / 32, 1e-6f);
}

// White furnace: with F = 1 (Schlick, F0 = 1) the conductor only loses energy,
// the light that single scattering drops (reflected below the surface or
// masked; multiple scattering would return it). Every sample's weight
// G2 / G1 is at most 1; the albedo E (mean weight, failed samples 0, 2 x 10^5
// samples) equals the integral of evalConductor over the sphere (C++, the
// chi-square tests' grids) within 5 standard errors + 1e-3, and that integral is at
// most 1 at every alpha and angle. At alpha 1 the loss has a closed form: D =
// 1 / pi and Lambda(w) = (1 / |z| - 1) / 2, so f |cos wi| = mu_i / (2 pi
// (mu_o + mu_i)) and E(mu_o) = 1 - mu_o ln(1 + 1 / mu_o): 1 - ln 2 = 0.307 at
// normal incidence; the integral matches it within 1e-3.
TEST(RoughConductor, WhiteFurnaceLosesOnlyTheMultipleScattering) {
    for (float a : {0.05f, 0.2f, 0.5f, 1.0f})
        for (double cosTheta : {1.0, 0.7, 0.3, 0.1, 0.02}) {
            SCOPED_TRACE(testing::Message() << "alpha " << a << " cos " << cosTheta);
            MicrofacetPush p =
                pushFor(MICROFACET_CONDUCTOR, glm::vec2(a), direction(cosTheta, 0.2), 11);
            p.count = 200000;
            double sum = 0, sum2 = 0;
            for (const auto& r : runRoutine(p)) {
                const double w = (r.flags & 1u) ? r.weight.x : 0.0;
                ASSERT_LE(w, 1.0 + 1e-6);
                sum += w;
                sum2 += w * w;
            }
            const double n = p.count, mean = sum / n;
            const double standardError = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
            const shared::Conductor conductor = conductorOf(p);
            const auto eval = [&](glm::vec3 wi) {
                return double(shared::evalConductor(conductor, p.wo, wi).x);
            };
            const double albedo = test::integrateOverSphere(gridFor(a, cosTheta), eval);
            EXPECT_LE(albedo, 1.0);
            EXPECT_NEAR(mean, albedo, 5 * standardError + 1e-3);
            const double mu = p.wo.z;
            if (a == 1.0f) {
                EXPECT_NEAR(albedo, 1 - mu * std::log(1 + 1 / mu), 1e-3);
            }
        }
}

// As alpha goes to 0 the conductor becomes the mirror. At normal incidence
// GGX puts half the visible normals within tan theta_m < alpha
// (P(tan theta_m < t) = t^2 / (alpha^2 + t^2)), so half the reflected
// directions lie within 2 atan(alpha) of the mirror direction (binomial
// z-test, Sidak-corrected); obliquely the median deviation is a few alpha and
// shrinks with it (measured 1.6 alpha at cos theta_o 0.6); the albedo
// approaches F(cos theta_o) (gold, complex Fresnel) within 0.05 alpha (measured
// 0.02 alpha at alpha 0.01, less below). Below VKP_MICROFACET_SMOOTH_ALPHA the
// sample is the delta: exactly the mirror direction, probability 1, weight
// F(cos theta_o) as the C++ side computes it (1e-5: GPU and CPU round the
// complex arithmetic differently).
TEST(RoughConductor, ApproachesTheMirrorAsAlphaGoesToZero) {
    for (float a : {1e-2f, 3e-3f, 1.01e-3f}) {
        SCOPED_TRACE(testing::Message() << "alpha " << a);
        MicrofacetPush p = pushFor(MICROFACET_CONDUCTOR, glm::vec2(a), glm::vec3(0, 0, 1), 13);
        p.fresnel = VKP_FRESNEL_COMPLEX;
        p.eta = GOLD_ETA;
        p.k = GOLD_K;
        double within = 0;
        for (const auto& r : runRoutine(p)) {
            ASSERT_EQ(r.flags & 2u, 0u);
            const glm::dvec3 d(r.direction);
            const double angle = std::atan2(std::hypot(d.x, d.y), d.z);
            if ((r.flags & 1u) && angle < 2 * std::atan(double(a))) within += 1;
        }
        const double n = p.count;
        EXPECT_LT(std::abs(within - n / 2) / std::sqrt(n / 4), Z_CRITICAL) << within;

        p.wo = direction(0.6, 0.5);
        const glm::dvec3 mirror(-p.wo.x, -p.wo.y, p.wo.z);
        const glm::vec3 fresnel = shared::fresnelComplex3(0.6f, GOLD_ETA, GOLD_K);
        std::vector<double> angles;
        glm::dvec3 sum(0);
        for (const auto& r : runRoutine(p)) {
            if (!(r.flags & 1u)) continue;
            const glm::dvec3 d(r.direction);
            angles.push_back(std::atan2(glm::length(glm::cross(d, mirror)), glm::dot(d, mirror)));
            sum += glm::dvec3(r.weight);
        }
        std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
        const double median = angles[angles.size() / 2];
        EXPECT_LT(median, 3 * a);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(sum[k] / n, fresnel[k], 0.05 * a);
    }
    MicrofacetPush p = pushFor(MICROFACET_CONDUCTOR, glm::vec2(0.99e-3f), direction(0.6, 0.5), 13);
    p.count = 1000;
    p.fresnel = VKP_FRESNEL_COMPLEX;
    p.eta = GOLD_ETA;
    p.k = GOLD_K;
    const glm::vec3 fresnel = shared::fresnelComplex3(p.wo.z, GOLD_ETA, GOLD_K);
    for (const auto& r : runRoutine(p)) {
        ASSERT_EQ(r.flags, 3u);                                       // valid, delta
        ASSERT_EQ(r.direction, glm::vec3(-p.wo.x, -p.wo.y, p.wo.z));  // exact: a sign flip
        ASSERT_EQ(r.pdf, 1.0f);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(r.weight[k], fresnel[k], 1e-5f);
    }
    const shared::Conductor smooth = conductorOf(p);
    const glm::vec3 mirror(-p.wo.x, -p.wo.y, p.wo.z);
    EXPECT_EQ(shared::evalConductor(smooth, p.wo, mirror), glm::vec3(0));
    EXPECT_EQ(shared::conductorPdf(smooth, p.wo, mirror), 0.0f);
}

// ---- rough dielectric --------------------------------------------------------------------

shared::RoughDielectric dielectricOf(const MicrofacetPush& p) {
    shared::RoughDielectric d{};
    d.alpha = p.alpha;
    d.ior = p.ior;
    d.reflectance = glm::vec3(1.0f);
    d.transmittance = glm::vec3(1.0f);
    return d;
}

// The density of the rough dielectric's wi, written in double from Walter et
// al. 2007 with the indices of both sides (no flipped frame, unlike the
// header): the microfacet normal m (m.z > 0) is the half vector
// normalize(wo + wi) for reflection and -(n_o wo + n_i wi) for transmission
// (eq. 16); wo must see m from its side (the visible normals of wo, or of -wo
// from below: G1(wo) |wo.m| D(m) / |wo.z|) and wi must leave on its side;
// the Jacobians are 1 / (4 |wo.m|) and n_i^2 |wi.m| / (n_o wo.m + n_i wi.m)^2
// (eqs. 14, 17); reflection is chosen with probability F(|wo.m|).
double dielectricDensity(glm::vec3 wof, glm::vec3 wif, glm::vec2 alpha, double ior) {
    const glm::dvec3 wo(wof), wi(wif);
    if (wo.z == 0 || wi.z == 0) return 0;
    const double no = wo.z > 0 ? 1 : ior, ni = wi.z > 0 ? 1 : ior;
    const bool reflection = wo.z * wi.z > 0;
    glm::dvec3 m = reflection ? wo + wi : -(no * wo + ni * wi);
    if (glm::dot(m, m) == 0) return 0;
    m = glm::normalize(m);
    if (m.z < 0) m = -m;
    const double om = glm::dot(wo, m), im = glm::dot(wi, m);
    if (om * wo.z <= 0 || im * wi.z <= 0) return 0;
    const double visible = double(shared::ggxG1(wof, alpha)) * std::abs(om) *
                           double(shared::ggxD(glm::vec3(m), alpha)) / std::abs(wo.z);
    // Fresnel for light arriving along wo at the microfacet, from wo's side.
    const double f =
        shared::fresnelDielectric(float(std::abs(om)), float(wo.z > 0 ? ior : 1 / ior));
    if (reflection) return f * visible / (4 * std::abs(om));
    const double denom = no * om + ni * im;
    return (1 - f) * visible * ni * ni * std::abs(im) / (denom * denom);
}

// Where two float evaluations of one configuration can disagree by the
// Fresnel term's rounding: test::fresnelRounding.
double fresnelRounding(const shared::RoughDielectric& d, glm::vec3 wo, glm::vec3 wi) {
    return test::fresnelRounding(d.ior, wo, wi);
}

struct DielectricCase {
    float ior;
    double cosTheta;  // > 0: wo outside, < 0: inside
    glm::vec2 alpha;
};

// Outside and inside, normal to grazing, narrow to rough, anisotropic; inside
// beyond the critical angle (41.8 degrees for 1.5: cos 0.745), where total
// internal reflection dominates and only steep microfacets transmit.
const DielectricCase DIELECTRIC_CASES[] = {
    {1.5f, 0.8, {0.2f, 0.2f}},    {1.5f, 1.0, {0.5f, 0.5f}},  {1.5f, 0.05, {0.5f, 0.5f}},
    {1.33f, 0.5, {0.05f, 0.05f}}, {1.5f, -0.9, {0.2f, 0.2f}}, {1.5f, -0.5, {0.2f, 0.2f}},
    {1.5f, -0.3, {0.05f, 0.05f}}, {2.4f, -0.7, {1.0f, 1.0f}}, {1.5f, 0.6, {0.05f, 0.4f}}};

MicrofacetPush dielectricPush(const DielectricCase& c, uint32_t seed) {
    MicrofacetPush p = pushFor(MICROFACET_DIELECTRIC, c.alpha, direction(c.cosTheta, 0.7), seed);
    p.ior = c.ior;
    return p;
}

// Reflection and transmission together follow the density above (chi-square
// on the whole sphere, failed samples their own cell; both lobes hold more
// than 1000 samples in every case), and each sample's pdf equals it to 1e-3
// relative (+ Fresnel's rounding near the critical angle). The pdf jumps
// where the transmitting microfacet reaches the horizon (GGX has horizontal
// normals), anywhere in a cell, so cells are integrated with 32 x 32 points:
// with 8 x 8 the integral at alpha 0.5, normal incidence, is 2e-3 low and
// the grazing case fails; 32 and 64 points agree to 1e-4.
TEST(RoughDielectric, SamplesFollowTheirDensity) {
    for (const DielectricCase& c : DIELECTRIC_CASES) {
        SCOPED_TRACE(testing::Message() << "ior " << c.ior << " cos " << c.cosTheta << " alpha "
                                        << c.alpha.x << ", " << c.alpha.y);
        const MicrofacetPush p = dielectricPush(c, 15);
        const auto results = runRoutine(p);
        const shared::RoughDielectric d = dielectricOf(p);
        auto pdf = [&](glm::vec3 wi) { return dielectricDensity(p.wo, wi, c.alpha, c.ior); };
        size_t reflected = 0, transmitted = 0;
        for (const auto& r : results) {
            if (!(r.flags & 1u)) continue;
            ASSERT_NEAR(r.pdf / pdf(r.direction), 1.0,
                        1e-3 + fresnelRounding(d, p.wo, r.direction));
            (r.direction.z * p.wo.z > 0 ? reflected : transmitted) += 1;
        }
        EXPECT_GT(reflected, 1000u);  // both lobes are exercised in every case
        EXPECT_GT(transmitted, 1000u);
        test::DirectionGrid grid = gridFor(std::min(c.alpha.x, c.alpha.y), c.cosTheta);
        grid.pointsPerAxis = 32;
        expectFits(grid, results, pdf, true);
    }
}

// Every sample's weight is eval / pdf, on the GPU and in C++ (1e-4 relative,
// + Fresnel's rounding near the critical angle; measured 1.4e-5 elsewhere);
// etaSquared is eta^2 for transmission (eta = n(wi side) / n(wo side)) and 1
// for reflection; and in flux (weight x etaSquared) no sample exceeds 1, the
// white furnace sample by sample.
TEST(RoughDielectric, WeightIsEvalOverPdf) {
    for (const DielectricCase& c : DIELECTRIC_CASES) {
        SCOPED_TRACE(testing::Message() << "ior " << c.ior << " cos " << c.cosTheta);
        const MicrofacetPush p = dielectricPush(c, 17);
        const shared::RoughDielectric d = dielectricOf(p);
        const float eta = c.cosTheta > 0 ? c.ior : 1 / c.ior;
        for (const auto& r : runRoutine(p)) {
            if (!(r.flags & 1u)) continue;
            ASSERT_EQ(r.flags, 1u);
            const bool transmitted = r.direction.z * p.wo.z < 0;
            ASSERT_EQ(r.etaSquared, transmitted ? eta * eta : 1.0f);
            ASSERT_LE(r.weight.x * r.etaSquared, 1.0f + 1e-6f);
            const glm::vec3 f = shared::evalRoughDielectric(d, p.wo, r.direction);
            const float pdf = shared::roughDielectricPdf(d, p.wo, r.direction);
            const double bound = 1e-4 + fresnelRounding(d, p.wo, r.direction);
            ASSERT_NEAR(r.evalPdf / r.pdf, 1.0, bound);
            ASSERT_NEAR(r.eval.x / r.evalPdf / r.weight.x, 1.0, bound) << "GPU eval";
            ASSERT_NEAR(f.x / pdf / r.weight.x, 1.0, bound) << "C++ eval";
        }
    }
}

// Reciprocity: reflection on either side f(wo, wi) = f(wi, wo); transmission
// the generalised f(wo, wi) / n(wo side)^2 = f(wi, wo) / n(wi side)^2 of the
// radiance form (Veach's thesis, chapter 5), to 1e-4 relative + Fresnel's
// rounding near the critical angle (measured 3.3e-6 elsewhere): the half
// vector computed with the two directions in opposite roles rounds
// differently. 40000 random pairs, random anisotropic alpha and ior.
TEST(RoughDielectric, Reciprocity) {
    std::mt19937 rng(23);
    std::normal_distribution<float> gauss;
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int reflections = 0, transmissions = 0, edgeOn = 0;
    for (int n = 0; n < 40000; ++n) {
        shared::RoughDielectric d{};
        d.alpha = glm::vec2(0.02f + uniform(rng), 0.02f + uniform(rng));
        d.ior = 1.1f + 1.5f * uniform(rng);
        d.reflectance = d.transmittance = glm::vec3(1.0f);
        const glm::vec3 a = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        const glm::vec3 b = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
        if (std::abs(a.z) < 1e-2f || std::abs(b.z) < 1e-2f) continue;
        const float fab = shared::evalRoughDielectric(d, a, b).x / std::abs(b.z);
        const float fba = shared::evalRoughDielectric(d, b, a).x / std::abs(a.z);
        if (fab == 0 && fba == 0) continue;
        const float na = a.z > 0 ? 1 : d.ior, nb = b.z > 0 ? 1 : d.ior;
        const double bound = 1e-4 + fresnelRounding(d, a, b) + fresnelRounding(d, b, a);
        if (fab == 0 || fba == 0) {
            // A microfacet seen edge-on from one side (wo.m ~ 1e-4): rounding
            // puts the reverse on the other side of the support's boundary,
            // where f is vanishing anyway.
            ASSERT_LT(std::max(fab, fba), 1e-6f);
            ++edgeOn;
            continue;
        }
        ASSERT_NEAR((fab / (na * na)) / (fba / (nb * nb)), 1.0, bound);
        (a.z * b.z > 0 ? reflections : transmissions) += 1;
    }
    EXPECT_GT(reflections, 5000);
    EXPECT_GT(transmissions, 5000);
    EXPECT_LT(edgeOn, 10);
}

// White furnace in flux: the albedo, reflection plus transmission times eta^2
// (the energy, not the radiance, that crosses), sampled (mean of weight x
// etaSquared, 2 x 10^5 samples) equals the integral of eval x (eta^2 where wi
// transmits) over the sphere within 5 standard errors + 1e-3, and that
// integral is at most 1 (ior 1.5, alpha 0.2 and 1, cos theta_o 0.9, 0.3,
// -0.9, -0.5). The loss is the single scattering's, as for the conductor
// (measured figures in docs/ACCURACY.md).
TEST(RoughDielectric, WhiteFurnaceLosesOnlyTheMultipleScattering) {
    for (float a : {0.2f, 1.0f})
        for (double cosTheta : {0.9, 0.3, -0.9, -0.5}) {
            SCOPED_TRACE(testing::Message() << "alpha " << a << " cos " << cosTheta);
            const MicrofacetPush p = [&] {
                MicrofacetPush q = dielectricPush({1.5f, cosTheta, glm::vec2(a)}, 19);
                q.count = 200000;
                return q;
            }();
            double sum = 0, sum2 = 0;
            for (const auto& r : runRoutine(p)) {
                const double w = (r.flags & 1u) ? r.weight.x * r.etaSquared : 0.0;
                sum += w;
                sum2 += w * w;
            }
            const double n = p.count, mean = sum / n;
            const double standardError = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
            const shared::RoughDielectric d = dielectricOf(p);
            const float eta = cosTheta > 0 ? p.ior : 1 / p.ior;
            const auto flux = [&](glm::vec3 wi) {
                const double f = shared::evalRoughDielectric(d, p.wo, wi).x;
                return wi.z * p.wo.z < 0 ? f * eta * eta : f;
            };
            const double albedo = test::integrateOverSphere(gridFor(a, cosTheta), flux);
            EXPECT_LE(albedo, 1.0);
            EXPECT_NEAR(mean, albedo, 5 * standardError + 1e-3);
        }
}

// As alpha goes to 0 the rough dielectric becomes the smooth one (ior 1.5,
// cos theta_o 0.6 and -0.9; alpha 1e-2, 3e-3, 1.01e-3): the reflected
// fraction approaches F(cos theta_o) within 5 standard errors + 0.05 alpha
// (measured within 2 standard errors), the median deviation of the
// transmitted directions from Snell's is below 3 alpha (measured 0.49 and
// 0.69 alpha), the flux albedo approaches 1 within 0.05 alpha (measured
// 0.012 alpha). Below VKP_MICROFACET_SMOOTH_ALPHA, and at index
// 1 whatever alpha, it IS the smooth glass: the same direction, pdf, weight
// and etaSquared as lobes.h's sampleDielectric given the same random number
// (recomputed here in C++ from the shared RNG), to 1e-5.
TEST(RoughDielectric, ApproachesSmoothGlassAsAlphaGoesToZero) {
    for (double cosTheta : {0.6, -0.9})
        for (float a : {1e-2f, 3e-3f, 1.01e-3f}) {
            SCOPED_TRACE(testing::Message() << "cos " << cosTheta << " alpha " << a);
            const MicrofacetPush p = dielectricPush({1.5f, cosTheta, glm::vec2(a)}, 21);
            const float eta = cosTheta > 0 ? 1.5f : 1 / 1.5f;
            const float fresnel = shared::fresnelDielectric(float(cosTheta), 1.5f);
            const double sinT = std::sqrt(1 - cosTheta * cosTheta) / eta;
            // Snell's direction: opposite side, azimuth turned by pi.
            const glm::dvec3 snell(-sinT * std::cos(0.7), -sinT * std::sin(0.7),
                                   (cosTheta > 0 ? -1 : 1) * std::sqrt(1 - sinT * sinT));
            double reflected = 0, flux = 0;
            std::vector<double> angles;
            for (const auto& r : runRoutine(p)) {
                if (!(r.flags & 1u)) continue;
                flux += r.weight.x * r.etaSquared;
                if (r.direction.z * p.wo.z > 0) {
                    reflected += 1;
                    continue;
                }
                const glm::dvec3 d(r.direction);
                angles.push_back(std::atan2(glm::length(glm::cross(d, snell)), glm::dot(d, snell)));
            }
            const double n = p.count;
            std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
            const double median = angles[angles.size() / 2];
            EXPECT_NEAR(reflected / n, fresnel,
                        5 * std::sqrt(fresnel * (1 - fresnel) / n) + 0.05 * a);
            EXPECT_LT(median, 3 * a);
            EXPECT_NEAR(flux / n, 1.0, 0.05 * a);
        }
    for (const auto& [ior, a] : {std::pair{1.5f, 0.99e-3f}, std::pair{1.0f, 0.5f}})
        for (double cosTheta : {0.6, -0.9, -0.5}) {
            SCOPED_TRACE(testing::Message()
                         << "ior " << ior << " alpha " << a << " cos " << cosTheta);
            MicrofacetPush p = dielectricPush({ior, cosTheta, glm::vec2(a)}, 25);
            p.count = 10000;
            const auto results = runRoutine(p);
            for (uint32_t i = 0; i < p.count; ++i) {
                const auto& r = results[i];
                const float uc = shared::rngUniform(shared::makeRngKey(i, 0u, p.seed), 2u);
                const shared::BsdfSample s = shared::sampleDielectric(
                    glm::vec3(1.0f), glm::vec3(1.0f), ior, glm::vec3(0, 0, 1), p.wo, uc);
                ASSERT_EQ(r.flags, 3u);  // valid, delta
                for (int k = 0; k < 3; ++k) ASSERT_NEAR(r.direction[k], s.direction[k], 1e-5f);
                ASSERT_NEAR(r.pdf, s.pdf, 1e-5f);
                ASSERT_NEAR(r.weight.x, s.weight.x, 1e-5f);
                ASSERT_EQ(r.etaSquared, s.etaSquared);
            }
            const shared::RoughDielectric d = dielectricOf(p);
            const glm::vec3 wi = -p.wo;
            EXPECT_EQ(shared::evalRoughDielectric(d, p.wo, wi), glm::vec3(0));
            EXPECT_EQ(shared::roughDielectricPdf(d, p.wo, wi), 0.0f);
        }
}

}  // namespace
