// Every sampling routine of shaders/shared/, run on the GPU: its samples
// follow its own pdf (chi-square, 10^6 samples), its pdf integrates to 1, and
// the discrete choices of the dielectric follow Fresnel. Significance: 1% for
// the whole file, Sidak-corrected over its chi-square and z tests.
#include "shared/sampling.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>

#include "kernels/sampling_routines.h"
#include "shared/bsdf.h"
#include "shared/phase.h"
#include "support/direction_chi2.h"
#include "support/test_context.h"
#include "support/test_scale.h"
#include "vk/buffer.h"
#include "vk/kernel.h"

namespace {

using namespace vkpath;
using shared::SamplingPush;
using shared::SamplingResult;

constexpr uint32_t SAMPLES = 1000000;
constexpr int TESTS_IN_FILE =
    13;  // 11 chi-square tests, the solid-angle z-test, the dielectric z-tests
const double ALPHA = test::sidakAlpha(0.01, TESTS_IN_FILE);

std::vector<SamplingResult> runRoutine(SamplingPush push) {
    vk::Context& context = test::context();
    vk::Buffer results(context, push.count * sizeof(SamplingResult));
    vk::Kernel kernel(context, "sampling_routines");
    kernel.dispatch(push.count, {{0, &results}}, push);
    return results.download<SamplingResult>();
}

SamplingPush pushFor(uint32_t routine, uint32_t seed = 1) {
    SamplingPush p{};
    p.routine = routine;
    p.count = SAMPLES;
    p.seed = seed;
    return p;
}

std::vector<glm::vec3> directionsOf(const std::vector<SamplingResult>& results) {
    std::vector<glm::vec3> d;
    d.reserve(results.size());
    for (const auto& r : results) d.push_back(r.direction);
    return d;
}

void expectFits(const test::DirectionGrid& grid, const std::vector<glm::vec3>& directions,
                const std::function<double(glm::vec3)>& pdf) {
    EXPECT_NEAR(test::integrateOverSphere(grid, pdf), 1.0, 1e-3) << "pdf does not integrate to 1";
    const auto result = test::chiSquareDirections(grid, directions, pdf);
    EXPECT_GT(result.pValue, ALPHA) << "chi2 " << result.statistic << ", dof "
                                    << result.degreesOfFreedom << ", pooled " << result.pooledCells;
}

// The concentric map's cosine and sine without libm: within one ulp of the
// correctly rounded values (double cos and sin rounded) over all of
// [-pi/4, pi/4], as glibc's cosf and sinf are there; 2^23 angles.
TEST(Sampling, QuarterPiCosineAndSineWithinOneUlp) {
    auto ordered = [](float f) {
        const int32_t bits = std::bit_cast<int32_t>(f);
        return bits < 0 ? int64_t(INT32_MIN) - bits : int64_t(bits);
    };
    int64_t worstCos = 0, worstSin = 0;
    constexpr int64_t STEPS = int64_t(1) << 22;
    for (int64_t k = -STEPS; k <= STEPS; ++k) {
        const float a = float(double(k) / double(STEPS) * (M_PI / 4.0));
        const glm::vec2 cs = shared::cosSinQuarterPi(a);
        worstCos =
            std::max(worstCos, std::abs(ordered(cs.x) - ordered(float(std::cos(double(a))))));
        worstSin =
            std::max(worstSin, std::abs(ordered(cs.y) - ordered(float(std::sin(double(a))))));
    }
    EXPECT_LE(worstCos, 1);
    EXPECT_LE(worstSin, 1);
}

TEST(Sampling, CosineHemisphere) {
    const auto results = runRoutine(pushFor(ROUTINE_COSINE_HEMISPHERE));
    for (const auto& r : results)
        ASSERT_NEAR(r.pdf, shared::cosineHemispherePdf(r.direction.z), 1e-5f);
    expectFits({}, directionsOf(results),
               [](glm::vec3 d) { return shared::cosineHemispherePdf(d.z); });
}

// The test has power: cosine-weighted samples do not pass as uniform ones.
TEST(Sampling, ChiSquareRejectsTheWrongPdf) {
    const auto directions = directionsOf(runRoutine(pushFor(ROUTINE_COSINE_HEMISPHERE)));
    const auto result = test::chiSquareDirections({}, directions, [](glm::vec3 d) {
        return d.z > 0 ? shared::uniformHemispherePdf() : 0.0f;
    });
    EXPECT_LT(result.pValue, 1e-10);
}

TEST(Sampling, UniformSphere) {
    expectFits({}, directionsOf(runRoutine(pushFor(ROUTINE_UNIFORM_SPHERE))),
               [](glm::vec3) { return shared::uniformSpherePdf(); });
}

TEST(Sampling, UniformHemisphere) {
    expectFits({}, directionsOf(runRoutine(pushFor(ROUTINE_UNIFORM_HEMISPHERE))),
               [](glm::vec3 d) { return d.z > 0 ? shared::uniformHemispherePdf() : 0.0f; });
}

TEST(Sampling, LambertianAroundAnArbitraryNormal) {
    SamplingPush p = pushFor(ROUTINE_LAMBERTIAN);
    p.a = glm::normalize(glm::vec3(0.3f, -0.8f, 0.52f));
    p.b = glm::normalize(
        glm::vec3(-0.9f, 0.9f, -0.2f));  // wo below the normal: reflects on wo's side
    const auto results = runRoutine(p);
    for (const auto& r : results) {
        ASSERT_EQ(r.flags & 1u, 1u);
        ASSERT_EQ(r.weight, glm::vec3(1.0f));  // albedo 1: f cos / pdf = 1
    }
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(p.a);
    expectFits(grid, directionsOf(results),
               [&](glm::vec3 d) { return shared::lambertianPdf(p.a, p.b, d); });
}

// The Henyey-Greenstein phase function (shared/phase.h), sampled around an
// arbitrary wo: isotropic, forward, backward and strongly forward (g 0.95,
// whose lobe lies within 1 - cos theta < 0.05 of -wo for half its samples: a
// grid whose cells shrink toward the poles). Every sample's pdf is its own
// density's value, and the pdf integrates to 1.
TEST(Sampling, HenyeyGreensteinPhaseFunction) {
    for (const float g : {0.0f, 0.5f, -0.7f, 0.95f}) {
        SCOPED_TRACE(g);
        SamplingPush p = pushFor(ROUTINE_HENYEY_GREENSTEIN, 3);
        p.b = glm::normalize(glm::vec3(0.2f, -0.5f, 0.8f));
        p.scalar = g;
        const auto results = runRoutine(p);
        for (const auto& r : results)
            ASSERT_NEAR(r.pdf, shared::henyeyGreenstein(glm::dot(p.b, r.direction), g),
                        1e-4f * r.pdf);
        test::DirectionGrid grid;
        grid.frame = shared::makeFrame(-p.b);
        if (g > 0.9f) grid.polarExponent = 3;
        expectFits(grid, directionsOf(results),
                   [&](glm::vec3 d) { return shared::henyeyGreenstein(glm::dot(p.b, d), g); });
    }
}

// The cone of a sphere light, seen from outside. The grid is aligned with the
// cone axis and the cone's edge (cos theta_max) is put at the middle of a
// cos-theta bin, where the even midpoint rule integrates the jump exactly.
TEST(Sampling, SphereLightCone) {
    const test::DirectionGrid grid0;
    const double cosThetaMax = -1.0 + (2 * 90 + 1) / double(grid0.cosBins);  // middle of bin 90
    const double distance = 5.0;
    SamplingPush p = pushFor(ROUTINE_SPHERE_CONE);
    p.a = glm::vec3(1.0f, 2.0f, -3.0f);
    const glm::vec3 axis = glm::normalize(glm::vec3(-0.4f, 0.7f, 0.3f));
    p.b = p.a + float(distance) * axis;
    p.scalar = float(distance * std::sqrt(1 - cosThetaMax * cosThetaMax));
    const auto results = runRoutine(p);
    const shared::SphereCone cone = shared::sphereCone(p.b, p.scalar, p.a);
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(axis);
    expectFits(grid, directionsOf(results), [&](glm::vec3 d) {
        return double(glm::dot(d, axis)) >= cone.cosThetaMax ? double(shared::sphereConePdf(cone))
                                                             : 0.0;
    });
}

// A far, tiny sphere (the sun seen from the earth subtends ~0.5 degrees; here
// 1e-3 radians): every sampled direction hits it, and the pdf equals
// 1 / (2 pi (1 - cos theta_max)) computed in double.
TEST(Sampling, TinySphereConeStaysOnTheSphere) {
    SamplingPush p = pushFor(ROUTINE_SPHERE_CONE);
    p.count = 100000;
    p.a = glm::vec3(0.0f);
    p.b = glm::vec3(0.0f, 1e4f, 0.0f);
    p.scalar = 10.0f;
    const auto results = runRoutine(p);
    const double sin2 = 1e-6, oneMinusCos = sin2 / (1 + std::sqrt(1 - sin2));
    const double expectedPdf = 1 / (2 * 3.14159265358979323846 * oneMinusCos);
    for (const auto& r : results) {
        ASSERT_NEAR(r.pdf, expectedPdf, expectedPdf * 1e-4);
        // Ray-sphere test in double: distance from the centre to the ray line.
        const glm::dvec3 d = glm::normalize(glm::dvec3(r.direction));
        const glm::dvec3 c(p.b);
        const double along = glm::dot(c, d);
        const double miss2 = glm::dot(c, c) - along * along;
        ASSERT_LE(miss2, 100.0 * (1 + 1e-3)) << "sampled direction misses the sphere";
    }
}

// Area sampling of a triangle: barycentrics uniform over the triangle, in a
// 64 x 64 grid over (b0, b1) whose diagonal cells are exactly half inside.
TEST(Sampling, TriangleAreaUniform) {
    SamplingPush p = pushFor(ROUTINE_TRIANGLE_AREA);
    p.a = glm::vec3(0, 0, 0);
    p.b = glm::vec3(2, 0, 0);
    p.c = glm::vec3(0, 1, 1);
    const auto results = runRoutine(p);
    constexpr int N = 64;
    std::vector<double> observed(N * N, 0), expected(N * N, 0);
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            const double fraction = i + j < N - 1 ? 1.0 : (i + j == N - 1 ? 0.5 : 0.0);
            expected[i * N + j] = SAMPLES * fraction * 2.0 / (N * N);
        }
    const float area = glm::length(shared::triangleArea3(p.a, p.b, p.c));
    for (const auto& r : results) {
        ASSERT_NEAR(r.pdf, 1.0f / area, 1e-6f);
        const int i = std::min(N - 1, int(r.direction.x * N)),
                  j = std::min(N - 1, int(r.direction.y * N));
        observed[i * N + j] += 1;
    }
    const auto result = test::chiSquareTest(observed, expected);
    EXPECT_GT(result.pValue, ALPHA)
        << "chi2 " << result.statistic << ", dof " << result.degreesOfFreedom;
}

// Area samples converted to solid angle estimate the triangle's solid angle:
// E[1 / pdf_omega] = Omega, against the exact formula of Van Oosterom and
// Strackee (IEEE Trans. Biomed. Eng. 30(2), 1983). Bound: 5 standard errors.
TEST(Sampling, TriangleSolidAngleFromAreaSamples) {
    SamplingPush p = pushFor(ROUTINE_TRIANGLE_AREA);
    p.a = glm::vec3(-1, 1, -2);
    p.b = glm::vec3(2, 0.5f, -2.5f);
    p.c = glm::vec3(0, 2, -1.5f);
    const auto results = runRoutine(p);
    const glm::dvec3 a(p.a), b(p.b), c(p.c);
    const double area = glm::length(glm::cross(b - a, c - a)) / 2;
    const glm::dvec3 normal = glm::normalize(glm::cross(b - a, c - a));
    double sum = 0, sum2 = 0;
    for (const auto& r : results) {
        const double b0 = r.direction.x, b1 = r.direction.y;
        const glm::dvec3 x = b0 * a + b1 * b + (1 - b0 - b1) * c;  // viewed from the origin
        const double dist2 = glm::dot(x, x);
        const double cosLight = glm::dot(normal, x) / std::sqrt(dist2);
        const double pdfOmega =
            shared::areaToSolidAnglePdf(float(area), float(dist2), float(cosLight));
        sum += 1 / pdfOmega;
        sum2 += 1 / (pdfOmega * pdfOmega);
    }
    const double n = double(results.size()), mean = sum / n;
    const double standardError = std::sqrt((sum2 / n - mean * mean) / n);
    const double numerator = std::abs(glm::dot(a, glm::cross(b, c)));
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double denominator =
        la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    const double exact = 2 * std::atan2(numerator, denominator);
    EXPECT_NEAR(mean, exact, 5 * standardError);
}

// A triangle light as seen from a point (the origin): area samples turned
// into directions follow the light's solid-angle pdf, t^2 / (A |cos theta_l|)
// along the directions that hit it and 0 elsewhere, as shade's next-event
// estimation uses it. The grid's pole points at the triangle. Its edges cut
// cells anywhere, so the cell integrals use 32 x 32 midpoints: the error of a
// straight edge through a cell is then ~1/(2 * 32^1.5) = 0.3% of the cell,
// a tenth of the Poisson noise of its ~1000 samples. The pdf of each sample
// (areaToSolidAnglePdf, float) must equal the one in double to 1e-4.
TEST(Sampling, TriangleLightDirectionsFromAPoint) {
    SamplingPush p = pushFor(ROUTINE_TRIANGLE_AREA, 3);
    p.a = glm::vec3(-1.5f, 1.0f, -2.0f);
    p.b = glm::vec3(2.0f, 0.5f, -2.5f);
    p.c = glm::vec3(0.0f, 2.5f, -1.0f);
    const auto results = runRoutine(p);
    const glm::dvec3 a(p.a), b(p.b), c(p.c);
    const glm::dvec3 cross = glm::cross(b - a, c - a);
    const double area = glm::length(cross) / 2;
    const glm::dvec3 normal = cross / glm::length(cross);
    // Solid-angle pdf of direction d from the origin (Moller-Trumbore in double).
    auto pdf = [&](glm::vec3 direction) -> double {
        const glm::dvec3 d = glm::normalize(glm::dvec3(direction));
        const glm::dvec3 e1 = b - a, e2 = c - a, q = glm::cross(d, e2);
        const double det = glm::dot(e1, q);
        if (std::abs(det) < 1e-300) return 0.0;
        const glm::dvec3 s0 = -a;
        const double u = glm::dot(s0, q) / det;
        const glm::dvec3 r = glm::cross(s0, e1);
        const double v = glm::dot(d, r) / det, t = glm::dot(e2, r) / det;
        if (u < 0 || v < 0 || u + v > 1 || t <= 0) return 0.0;
        return t * t / (area * std::abs(glm::dot(normal, d)));
    };
    std::vector<glm::vec3> directions;
    directions.reserve(results.size());
    for (const auto& r : results) {
        const glm::dvec3 x = double(r.direction.x) * a + double(r.direction.y) * b +
                             (1 - double(r.direction.x) - double(r.direction.y)) * c;
        const glm::dvec3 d = glm::normalize(x);
        const double cosLight = glm::dot(normal, d);
        const float shaded =
            shared::areaToSolidAnglePdf(float(area), float(glm::dot(x, x)), float(cosLight));
        const double exact = glm::dot(x, x) / (area * std::abs(cosLight));
        ASSERT_NEAR(shaded, exact, 1e-4 * exact);
        directions.push_back(glm::vec3(d));
    }
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(glm::vec3(glm::normalize(a + b + c)));
    grid.pointsPerAxis = 32;
    expectFits(grid, directions, pdf);
    // Power: the same samples judged against the pdf without the light's
    // cosine (area to solid angle by t^2 alone, renormalised) are rejected.
    auto noCosine = [&](glm::vec3 d) {
        return pdf(d) * std::abs(glm::dot(normal, glm::normalize(glm::dvec3(d))));
    };
    const double total = test::integrateOverSphere(grid, noCosine);
    const auto wrong = test::chiSquareDirections(grid, directions,
                                                 [&](glm::vec3 d) { return noCosine(d) / total; });
    EXPECT_LT(wrong.pValue, 1e-10) << "chi2 " << wrong.statistic;
}

// ---- the dielectric ---------------------------------------------------------------

TEST(Fresnel, AnalyticValues) {
    EXPECT_NEAR(shared::fresnelDielectric(1.0f, 1.5f), 0.04f, 1e-6f);  // ((1.5-1)/(1.5+1))^2
    EXPECT_NEAR(shared::fresnelDielectric(-1.0f, 1.5f), 0.04f,
                1e-6f);  // symmetric at normal incidence
    // From glass (1.5) to air at 45 degrees: sin 45 * 1.5 = 1.06 > 1, total internal reflection.
    EXPECT_EQ(shared::fresnelDielectric(-std::sqrt(0.5f), 1.5f), 1.0f);
    // Just inside the critical angle (41.8 degrees) there is still transmission.
    EXPECT_LT(shared::fresnelDielectric(-std::cos(0.70f), 1.5f), 1.0f);
    // Index 1 is no interface at all.
    EXPECT_EQ(shared::fresnelDielectric(0.3f, 1.0f), 0.0f);
    // Grazing incidence reflects everything.
    EXPECT_NEAR(shared::fresnelDielectric(1e-7f, 1.5f), 1.0f, 1e-5f);
}

struct DielectricCase {
    float ior;
    float cosThetaO;  // > 0: wo outside, < 0: wo inside
};

// The reflect/refract choice follows Fresnel (binomial z-test), reflection is
// the mirror direction, refraction obeys Snell's law, and refracted radiance
// is scaled by 1/eta^2, for indices 1.0, 1.33, 1.5, 2.4 and 10, from both
// sides and past the critical angle. 2 x 10^5 samples per case in CI (the
// z-test's power: a reflection probability off by 0.01 moves z by 4.5 at
// F = 0.5), 10^6 under `make test-long`.
TEST(Dielectric, ChoiceDirectionsAndWeights) {
    // ior 10 from inside: the critical angle has cosine 0.995, so -0.999 refracts and -0.9 reflects
    // totally.
    const DielectricCase cases[] = {{1.0f, 0.7f},  {1.33f, 0.9f}, {1.33f, -0.9f}, {1.5f, 0.2f},
                                    {1.5f, -0.8f}, {1.5f, -0.5f}, {2.4f, 0.6f},   {2.4f, -0.95f},
                                    {1.5f, 1.0f},  {10.0f, 0.5f}, {10.0f, 1e-3f}, {10.0f, -0.999f},
                                    {10.0f, -0.9f}};
    const glm::vec3 n = glm::normalize(glm::vec3(0.2f, 0.9f, -0.3f));
    const shared::Frame frame = shared::makeFrame(n);
    const double zCritical = 4.0;  // two-sided; p ~ 6e-5 per case, well under ALPHA / cases
    for (const DielectricCase& c : cases) {
        SCOPED_TRACE(testing::Message() << "ior " << c.ior << " cos " << c.cosThetaO);
        SamplingPush p = pushFor(ROUTINE_DIELECTRIC, 5);
        p.count = test::ciOrLong(200000u, 1000000u);
        p.scalar = c.ior;
        p.a = n;
        const float sinO = std::sqrt(1 - c.cosThetaO * c.cosThetaO);
        p.b = glm::normalize(shared::frameToWorld(frame, glm::vec3(sinO, 0, c.cosThetaO)));
        const auto results = runRoutine(p);
        const float fresnel = shared::fresnelDielectric(c.cosThetaO, c.ior);
        const bool outside = c.cosThetaO > 0;
        const float eta = outside ? c.ior : 1 / c.ior;
        double reflections = 0;
        for (const auto& r : results) {
            ASSERT_EQ(r.flags, 3u);  // valid and delta
            const float cosI = glm::dot(r.direction, n);
            if (cosI * c.cosThetaO > 0) {
                reflections += 1;
                ASSERT_NEAR(cosI, c.cosThetaO, 1e-5f);
                ASSERT_NEAR(r.pdf, fresnel, 1e-6f);
                ASSERT_EQ(r.weight, glm::vec3(1.0f));
            } else {
                // Snell: sin_t = sin_o / eta, measured in the frame of n.
                const float sinT = std::sqrt(std::max(0.0f, 1 - cosI * cosI));
                ASSERT_NEAR(sinT, sinO / eta, 2e-5f);
                ASSERT_NEAR(r.pdf, 1 - fresnel, 1e-6f);
                ASSERT_NEAR(r.weight.x, 1 / (eta * eta), 1e-6f / (eta * eta));
            }
        }
        const double n0 = double(results.size());
        const double expected = n0 * fresnel;
        const double sigma = std::sqrt(n0 * fresnel * (1 - fresnel));
        if (sigma > 0)
            EXPECT_LT(std::abs(reflections - expected) / sigma, zCritical)
                << "reflected " << reflections;
        else
            EXPECT_EQ(reflections, expected);
    }
}

TEST(Mirror, ReflectsOnTheSideOfWo) {
    SamplingPush p = pushFor(ROUTINE_MIRROR);
    p.count = 64;
    p.a = glm::vec3(0, 0, 1);
    p.b = glm::normalize(glm::vec3(0.6f, 0.0f, -0.8f));  // from behind: two-sided
    for (const auto& r : runRoutine(p)) {
        EXPECT_NEAR(r.direction.x, -0.6f, 1e-6f);
        EXPECT_NEAR(r.direction.z, -0.8f, 1e-6f);
        EXPECT_EQ(r.flags, 3u);
    }
}

// Index exactly 1 is no interface: Fresnel gives exactly 0, so every sample
// refracts with probability 1 and weight exactly 1, and the direction goes on
// unchanged: -wo up to the rounding of Snell's formula, whose cos_t =
// sqrt(1 - sin^2) turns an ulp of 1 - cos^2 into ~ulp / (2 cos): bound 4 ulps
// of 1 (4.8e-7) / |cos theta_o| (measured 3.4e-6 at cos 1e-3).
TEST(Dielectric, IndexOneLeavesDirectionAndWeightUnchanged) {
    const glm::vec3 n = glm::normalize(glm::vec3(-0.5f, 0.3f, 0.8f));
    const shared::Frame frame = shared::makeFrame(n);
    for (float cosO : {1.0f, 0.7f, 1e-3f, -0.4f, -0.999f}) {
        SCOPED_TRACE(cosO);
        SamplingPush p = pushFor(ROUTINE_DIELECTRIC, 9);
        p.count = 10000;
        p.scalar = 1.0f;
        p.a = n;
        p.b = glm::normalize(
            shared::frameToWorld(frame, glm::vec3(std::sqrt(1 - cosO * cosO), 0, cosO)));
        for (const auto& r : runRoutine(p)) {
            ASSERT_EQ(r.flags, 3u);
            ASSERT_EQ(r.pdf, 1.0f);
            ASSERT_EQ(r.weight, glm::vec3(1.0f));
            for (int k = 0; k < 3; ++k)
                ASSERT_NEAR(r.direction[k], -p.b[k], 4.8e-7f / std::abs(cosO));
        }
    }
}

// ---- energy and reciprocity of every BSDF ----------------------------------------

// White furnace: with white parameters each BSDF reflects (and transmits)
// exactly the energy it receives, never more. The sampled weight is the
// estimator of the albedo, so every sample's weight must be at most 1
// (exactly 1 here): the Lambertian's and the mirror's, and the dielectric's
// once its refraction weight is taken back from radiance to flux (times
// eta^2, PBR 4th ed. section 9.5.2). Independently of sampling, the
// Lambertian's evaluation (what light sampling uses) integrates to its albedo
// over the sphere (to 1e-3, the grid's integration error being ~1e-5), and
// eval / pdf equals the sampled weight (MIS needs the two to agree).
TEST(Bsdf, WhiteFurnaceAlbedoAtMostOne) {
    const glm::vec3 n = glm::normalize(glm::vec3(0.1f, -0.7f, 0.4f));
    const glm::vec3 wo = glm::normalize(glm::vec3(0.6f, -0.5f, -0.2f));
    SamplingPush p = pushFor(ROUTINE_LAMBERTIAN, 11);
    p.count = 100000;
    p.a = n;
    p.b = wo;
    for (const auto& r : runRoutine(p)) {
        ASSERT_EQ(r.weight, glm::vec3(1.0f));
        const glm::vec3 f = shared::evalLambertian(glm::vec3(1.0f), n, wo, r.direction);
        ASSERT_NEAR(f.x / shared::lambertianPdf(n, wo, r.direction), 1.0f, 1e-5f);
    }
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(n);
    EXPECT_NEAR(test::integrateOverSphere(
                    grid,
                    [&](glm::vec3 d) {
                        return double(shared::evalLambertian(glm::vec3(1.0f), n, wo, d).x);
                    }),
                1.0, 1e-3);

    p.routine = ROUTINE_MIRROR;
    p.count = 64;
    for (const auto& r : runRoutine(p)) ASSERT_EQ(r.weight, glm::vec3(1.0f));

    for (float ior : {1.0f, 1.33f, 1.5f, 2.4f, 10.0f})
        for (float cosO : {0.9f, 0.3f, -0.3f, -0.9f}) {
            SCOPED_TRACE(testing::Message() << "ior " << ior << " cos " << cosO);
            SamplingPush d = pushFor(ROUTINE_DIELECTRIC, 13);
            d.count = 10000;
            d.scalar = ior;
            d.a = n;
            const shared::Frame frame = shared::makeFrame(n);
            d.b = glm::normalize(
                shared::frameToWorld(frame, glm::vec3(std::sqrt(1 - cosO * cosO), 0, cosO)));
            const float eta = cosO > 0 ? ior : 1 / ior;
            for (const auto& r : runRoutine(d)) {
                const bool refracted = glm::dot(r.direction, n) * cosO < 0;
                const float flux = r.weight.x * (refracted ? eta * eta : 1.0f);
                ASSERT_LE(flux, 1.0f + 1e-6f);
                ASSERT_GE(flux, 1.0f - 1e-6f);
            }
        }
}

// Reciprocity. Lambertian: f(wo, wi) = f(wi, wo) (evaluation divided by the
// cosine it includes), to float rounding. Dielectric (delta): the light path
// reversed retraces itself: refracting the refracted direction gives back wo,
// with the same probability (Fresnel is the same from both sides of a
// refraction, Stokes' relations) and reciprocal radiance weights (1/eta^2 one
// way, eta^2 the other: product 1 to 1e-5), the generalised reciprocity
// f(wo, wi) / eta_i^2 = f(wi, wo) / eta_o^2 of PBR 4th ed., 9.5.2. Going back
// multiplies sin theta by the index, so a float rounding of the first
// direction comes back ior / cos theta_o times larger: direction and
// probability to 4e-6 x ior / |cos theta_o| (measured 9.6e-5 and 1.8e-5 at
// ior 10, cos 0.1, where the bound is 4e-4).
TEST(Bsdf, Reciprocity) {
    std::mt19937 rng(17);
    std::normal_distribution<float> gauss;
    auto randomDirection = [&] {
        return glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
    };
    for (int i = 0; i < 10000; ++i) {
        const glm::vec3 n = randomDirection(), a = randomDirection(), b = randomDirection();
        const float ca = std::abs(glm::dot(n, a)), cb = std::abs(glm::dot(n, b));
        if (ca < 1e-3f || cb < 1e-3f) continue;
        const float fab = shared::evalLambertian(glm::vec3(0.8f), n, a, b).x / cb;
        const float fba = shared::evalLambertian(glm::vec3(0.8f), n, b, a).x / ca;
        ASSERT_NEAR(fab, fba, 1e-6f);
    }

    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 0.2f, -0.9f));
    const shared::Frame frame = shared::makeFrame(n);
    for (float ior : {1.33f, 1.5f, 2.4f, 10.0f})
        for (float cosO : {0.95f, 0.5f, 0.1f, -0.999f, -0.97f}) {
            const float eta = cosO > 0 ? ior : 1 / ior;
            if ((1 - cosO * cosO) / (eta * eta) >= 1)
                continue;  // total internal reflection: nothing to reverse
            SCOPED_TRACE(testing::Message() << "ior " << ior << " cos " << cosO);
            SamplingPush there = pushFor(ROUTINE_DIELECTRIC, 19);
            there.count = 256;
            there.scalar = ior;
            there.a = n;
            there.b = glm::normalize(
                shared::frameToWorld(frame, glm::vec3(std::sqrt(1 - cosO * cosO), 0, cosO)));
            SamplingResult forward{};
            for (const auto& r : runRoutine(there))
                if (glm::dot(r.direction, n) * cosO < 0) forward = r;
            ASSERT_NE(forward.pdf, 0.0f) << "no refraction among 256 samples";
            SamplingPush back = there;
            back.b = forward.direction;
            SamplingResult backward{};
            for (const auto& r : runRoutine(back))
                if (glm::dot(r.direction, n) * glm::dot(back.b, n) < 0) backward = r;
            ASSERT_NE(backward.pdf, 0.0f);
            const float tolerance = 4e-6f * ior / std::abs(cosO);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(backward.direction[k], there.b[k], tolerance);
            EXPECT_NEAR(backward.pdf, forward.pdf, tolerance);
            EXPECT_NEAR(forward.weight.x * backward.weight.x, 1.0f, 1e-5f);
        }
}

}  // namespace
