// KHR_materials_anisotropy through shared/bsdf.h's dispatch, sampled on the
// GPU by tests/kernels/bsdf_dispatch.comp: the alphas the extension defines,
// the lobe stretched along the per-hit direction (chi-square against
// anisotropic GGX written here in double in the test's own frame, and its
// power to tell the direction turned by 90 degrees), the metallic-roughness
// material and rough glass following their own density, and the compensated
// white metal's furnace with the isotropic table read at the alphas' root
// mean square.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "albedo/albedo_integrals.h"
#include "image/statistics.h"
#include "kernels/microfacet_routines.h"
#include "scene/scene.h"
#include "shared/bsdf.h"
#include "support/bsdf_dispatch_run.h"
#include "support/direction_chi2.h"
#include "support/test_scenes.h"

namespace {

using namespace vkpath;
using shared::MicrofacetResult;

constexpr uint32_t SAMPLES = 1000000;
constexpr double PI = 3.14159265358979323846;
// Statistical tests in this file: chi-square of the conductor 2, of the
// metallic-roughness material and rough glass 2, the furnace 3.
constexpr int STATISTICAL_TESTS = 7;
const double ALPHA = test::sidakAlpha(0.01, STATISTICAL_TESTS);
const double Z_CRITICAL = image::normalCritical(ALPHA);

const glm::vec3 NORMAL = test::DISPATCH_NORMAL;
// The per-hit direction (world space, not quite orthogonal to NORMAL: the
// dispatch makes it so), 30 degrees from makeFrame(NORMAL)'s s toward its t.
glm::vec3 direction(double degrees) {
    const shared::Frame f = shared::makeFrame(NORMAL);
    const double a = degrees * PI / 180;
    return glm::normalize(float(std::cos(a)) * f.s + float(std::sin(a)) * f.t + 0.2f * NORMAL);
}

// The frame whose s is `d` made orthogonal to NORMAL, built here.
shared::Frame testFrame(glm::vec3 d) {
    const glm::dvec3 n(NORMAL);
    const glm::dvec3 s = glm::normalize(glm::dvec3(d) - glm::dot(glm::dvec3(d), n) * n);
    return {glm::vec3(s), glm::vec3(glm::cross(n, s)), NORMAL};
}

glm::vec3 worldDirection(const shared::Frame& frame, double cosTheta, double phi) {
    return test::directionInFrame(frame, cosTheta, phi);
}

scene::Material anisotropic(scene::MaterialKind kind, float roughness, float strength) {
    scene::Material m;
    m.kind = kind;
    m.reflectance = glm::vec3(1.0f);
    m.roughness = roughness;
    m.anisotropy = strength;
    m.anisotropyRotation = 0.7f;  // (the scene's array; the per-hit direction replaces it)
    return m;
}

// The material as a hit sets it: the direction in world space.
shared::Material atHit(const scene::Material& m, glm::vec3 d) {
    shared::Material g = test::gpuMaterial(m);
    g.anisotropyDirection = d;
    return g;
}

std::vector<MicrofacetResult> runDispatch(const shared::Material& material, glm::vec3 wo,
                                          uint32_t seed) {
    return test::runBsdfDispatch(material, wo, NORMAL, seed, SAMPLES);
}

// Anisotropic GGX (Walter et al. 2007 eq. 33, Heitz 2014 eq. 85) and its
// Smith G1 (Heitz 2014 eq. 86), alphas ax along the frame's s and ay along t.
double ggxD(glm::dvec3 m, double ax, double ay) {
    if (m.z <= 0) return 0;
    const double e = m.x * m.x / (ax * ax) + m.y * m.y / (ay * ay) + m.z * m.z;
    return 1 / (PI * ax * ay * e * e);
}
double smithG1(glm::dvec3 w, double ax, double ay) {
    const double t2 = (w.x * w.x * ax * ax + w.y * w.y * ay * ay) / (w.z * w.z);
    return 2 / (1 + std::sqrt(1 + t2));
}

// The density of the reflected visible-normal sample (Heitz 2018: D_wo(h) =
// G1(wo) max(0, wo.h) D(h) / wo.z, times the Jacobian 1 / (4 wo.h)) in
// `frame`, the roughness r and strength s giving the extension's alphas.
double stretchedDensity(const shared::Frame& frame, double r, double s, glm::vec3 wo,
                        glm::vec3 wi) {
    const glm::dvec3 o(shared::frameToLocal(frame, wo)), i(shared::frameToLocal(frame, wi));
    if (i.z <= 0) return 0;
    const double a = r * r, ax = a + (1 - a) * s * s, ay = std::max(a, 1e-3);
    const glm::dvec3 h = glm::normalize(o + i);
    const double oh = glm::dot(o, h);
    if (oh <= 0) return 0;
    return smithG1(o, ax, ay) * ggxD(h, ax, ay) / (4 * o.z);
}

test::DirectionGrid gridAround(const shared::Frame& frame) {
    test::DirectionGrid grid;
    grid.frame = frame;
    grid.polarExponent = 2;
    return grid;
}

std::vector<glm::vec3> validDirections(const std::vector<MicrofacetResult>& results) {
    std::vector<glm::vec3> valid;
    for (const MicrofacetResult& r : results)
        if (r.flags & 1u) {
            EXPECT_EQ(r.flags & 2u, 0u) << "an anisotropic lobe's sample marked delta";
            EXPECT_NEAR(r.pdf / r.evalPdf, 1.0, 1e-3) << "sample pdf against bsdfPdf";
            valid.push_back(r.direction);
        }
    return valid;
}

TEST(Anisotropy, AlphasAreTheExtensions) {
    scene::Material m = anisotropic(scene::MaterialKind::Conductor, 0.5f, 0.6f);
    const glm::vec2 alpha = shared::materialAlpha(test::gpuMaterial(m));
    EXPECT_FLOAT_EQ(alpha.x, 0.25f + 0.75f * 0.36f);  // mix(alpha, 1, strength^2)
    EXPECT_FLOAT_EQ(alpha.y, 0.25f);
    // A smooth surface with anisotropy is a rough lobe along the direction,
    // its alpha across clamped to 0.001: never a delta.
    m.roughness = 0.0f;
    const glm::vec2 smooth = shared::materialAlpha(test::gpuMaterial(m));
    EXPECT_FLOAT_EQ(smooth.x, 0.36f);
    EXPECT_FLOAT_EQ(smooth.y, VKP_MICROFACET_SMOOTH_ALPHA);
    EXPECT_TRUE(shared::hasNonDeltaLobe(test::gpuMaterial(m)));
    // Strength 0 is the isotropic lobe.
    m.anisotropy = 0.0f;
    EXPECT_EQ(shared::materialAlpha(test::gpuMaterial(m)), glm::vec2(0.0f));
}

// A white metal (F = 1) of roughness 0.2 and strength 0.7: its samples follow
// the stretched GGX in the frame of the hit's direction, from two angles;
// the same samples judged against the lobe turned by 90 degrees are rejected.
TEST(Anisotropy, ConductorSamplesFollowTheStretchedLobe) {
    const float roughness = 0.2f, strength = 0.7f;
    const glm::vec3 d = direction(30);
    const shared::Material m =
        atHit(anisotropic(scene::MaterialKind::Conductor, roughness, strength), d);
    const shared::Frame frame = testFrame(d);
    for (const double cosTheta : {0.8, 0.3}) {
        SCOPED_TRACE(cosTheta);
        const glm::vec3 wo = worldDirection(frame, cosTheta, 1.1);
        const auto results = runDispatch(m, wo, 3);
        const std::vector<glm::vec3> valid = validDirections(results);
        auto pdf = [&](glm::vec3 wi) {
            return stretchedDensity(frame, roughness, strength, wo, wi);
        };
        const test::DirectionGrid grid = gridAround(frame);
        const auto fit =
            test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(), pdf);
        EXPECT_GT(fit.pValue, ALPHA)
            << "chi2 " << fit.statistic << ", dof " << fit.degreesOfFreedom;
        const shared::Frame turned = testFrame(direction(120));
        auto turnedPdf = [&](glm::vec3 wi) {
            return stretchedDensity(turned, roughness, strength, wo, wi);
        };
        EXPECT_LT(test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(),
                                                      turnedPdf)
                      .pValue,
                  1e-10);
    }
}

// The metallic-roughness material (a half-metal over a diffuse base) and
// rough glass, anisotropic: their samples follow their own bsdfPdf (the
// density the dispatch evaluates, here on the host: shared/bsdf.h compiled
// as C++), over the whole sphere for the glass.
TEST(Anisotropy, LayeredAndGlassSamplesFollowTheirDensity) {
    scene::Material plastic = anisotropic(scene::MaterialKind::MetallicRoughness, 0.3f, 0.8f);
    plastic.reflectance = {0.7f, 0.3f, 0.1f};
    plastic.metallic = 0.4f;
    scene::Material glass = anisotropic(scene::MaterialKind::RoughDielectric, 0.25f, 0.6f);
    glass.ior = 1.5f;
    const glm::vec3 d = direction(-50);
    for (const scene::Material& material : {plastic, glass}) {
        SCOPED_TRACE(scene::materialKindInfo(material.kind).key);
        const shared::Material m = atHit(material, d);
        const glm::vec3 wo = worldDirection(testFrame(d), 0.6, 2.0);
        const auto results = runDispatch(m, wo, 5);
        const std::vector<glm::vec3> valid = validDirections(results);
        auto pdf = [&](glm::vec3 wi) { return double(shared::bsdfPdf(m, NORMAL, NORMAL, wo, wi)); };
        const auto fit = test::chiSquareDirectionsWithLosses(gridAround(testFrame(d)), valid,
                                                             results.size() - valid.size(), pdf);
        EXPECT_GT(fit.pValue, ALPHA)
            << "chi2 " << fit.statistic << ", dof " << fit.degreesOfFreedom;
    }
}

// White furnace: glTF's white metal (Schlick F0 = 1: F = 1), anisotropic,
// compensated as a path vertex does (shared/path/energy_compensation.h, the
// isotropic lobe's albedo at the root mean square of the two alphas, here
// from the integral the table holds). The mean weight is then E_aniso /
// E_iso, which that stand-in keeps within 8% of 1 up to strength 0.6 and
// within 30% at strength 1 (measured over roughness 0.1-0.8, cos theta
// 0.9-0.2 and wo's azimuth along, diagonal to and across the direction; the
// worst cases are grazing, across it). Judged at the corners of that grid
// by a z-test with the samples' standard error plus that bound; an
// uncompensated lobe of strength 1 loses half its light there.
TEST(Anisotropy, CompensatedWhiteMetalKeepsItsLightWithinTheApproximation) {
    struct Case {
        float roughness, strength, cosTheta;
        double phi, bound;
    };
    const Case cases[] = {{0.1f, 0.6f, 0.2f, 1.57, 0.08},
                          {0.5f, 0.3f, 0.9f, 0.0, 0.08},
                          {0.3f, 1.0f, 0.5f, 0.8, 0.30}};
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message() << "roughness " << c.roughness << ", strength "
                                        << c.strength << ", cos " << c.cosTheta);
        const glm::vec3 d = direction(10);
        shared::Material m =
            atHit(anisotropic(scene::MaterialKind::Conductor, c.roughness, c.strength), d);
        const glm::vec2 alpha = shared::materialAlpha(m);
        const float rms = std::sqrt(0.5f * (alpha.x * alpha.x + alpha.y * alpha.y));
        const double e = albedo::conductorAlbedo(c.cosTheta, std::sqrt(rms));
        m.multipleScattering = float((1 - e) / e);
        const test::MeanWeight w =
            test::meanWeight(runDispatch(m, worldDirection(testFrame(d), c.cosTheta, c.phi), 9));
        EXPECT_LT(std::abs(w.mean - 1.0), Z_CRITICAL * w.standardError + c.bound)
            << "mean " << w.mean << ", standard error " << w.standardError;
    }
}

}  // namespace
