// The clear coat on a normal of its own (KHR_materials_clearcoat's
// clearcoatNormalTexture; Material::clearcoatNormal per hit), through
// shared/bsdf.h's dispatch on the GPU (tests/kernels/bsdf_dispatch.comp):
// the rough coat's samples follow the material's density (chi-square, with
// the power to tell the coat on the shading normal), the smooth coat
// mirrors wo about its own normal with weight F_c at that normal, and a
// smooth coat over glTF's compensated white metal returns all the light.
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
// Statistical tests in this file: the chi-square 1, the smooth coat's
// choice 1, the furnace 1.
constexpr int STATISTICAL_TESTS = 3;
const double ALPHA = test::sidakAlpha(0.01, STATISTICAL_TESTS);
const double Z_CRITICAL = image::normalCritical(ALPHA);

const glm::vec3 NORMAL = test::DISPATCH_NORMAL;

// The direction at angle `degrees` from NORMAL toward makeFrame(NORMAL)'s s.
glm::vec3 tilted(double degrees) {
    const shared::Frame f = shared::makeFrame(NORMAL);
    const double a = degrees * 3.14159265358979323846 / 180;
    return glm::normalize(float(std::cos(a)) * NORMAL + float(std::sin(a)) * f.s);
}

// wo at cosine cosTheta to NORMAL, azimuth phi in its frame.
glm::vec3 worldDirection(double cosTheta, double phi) {
    return test::directionInFrame(shared::makeFrame(NORMAL), cosTheta, phi);
}

// glTF's metallic-roughness material of `base`, metallic, roughness under a
// coat of weight 1 and roughness `coatRoughness` on `coatNormal` (0: the
// shading normal).
shared::Material coated(glm::vec3 base, float metallic, float roughness, float coatRoughness,
                        glm::vec3 coatNormal) {
    scene::Material m;
    m.kind = scene::MaterialKind::MetallicRoughness;
    m.reflectance = base;
    m.metallic = metallic;
    m.roughness = roughness;
    m.clearcoat = 1.0f;
    m.clearcoatRoughness = coatRoughness;
    shared::Material g = test::gpuMaterial(m);
    g.clearcoatNormal = coatNormal;
    return g;
}

// A rough coat (0.3) over red plastic, its normal 20 degrees off the
// shading normal: the samples follow the density the dispatch evaluates
// (bsdfPdf, here on the host: the coat's GGX lobe about its own normal, the
// base's about the shading normal, each weighted by the layer choice at its
// normal), each sample's pdf is bsdfPdf's and its weight evalBsdf / bsdfPdf;
// judged against the coat on the shading normal, they are rejected.
TEST(ClearcoatNormal, RoughCoatSamplesFollowTheirDensity) {
    const shared::Material m = coated({0.6f, 0.05f, 0.05f}, 0.0f, 0.6f, 0.3f, tilted(20));
    const glm::vec3 wo = worldDirection(0.7, 2.5);
    const auto results = test::runBsdfDispatch(m, wo, NORMAL, 3, SAMPLES);
    std::vector<glm::vec3> valid;
    for (const MicrofacetResult& r : results) {
        if (!(r.flags & 1u)) continue;
        ASSERT_EQ(r.flags & 2u, 0u);
        EXPECT_NEAR(r.pdf / r.evalPdf, 1.0, 1e-3);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(r.weight[k], r.eval[k] / r.evalPdf, 1e-4 * (1 + r.eval[k] / r.evalPdf));
        if (testing::Test::HasFailure()) return;
        valid.push_back(r.direction);
    }
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(NORMAL);
    grid.polarExponent = 2;
    auto pdf = [&](glm::vec3 wi) { return double(shared::bsdfPdf(m, NORMAL, NORMAL, wo, wi)); };
    EXPECT_LE(test::integrateOverSphere(grid, pdf), 1.0 + 1e-3);
    const auto fit =
        test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(), pdf);
    EXPECT_GT(fit.pValue, ALPHA) << "chi2 " << fit.statistic << ", dof " << fit.degreesOfFreedom;
    const shared::Material flat = coated({0.6f, 0.05f, 0.05f}, 0.0f, 0.6f, 0.3f, glm::vec3(0.0f));
    auto flatPdf = [&](glm::vec3 wi) {
        return double(shared::bsdfPdf(flat, NORMAL, NORMAL, wo, wi));
    };
    EXPECT_LT(
        test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(), flatPdf)
            .pValue,
        1e-10);
}

// A smooth coat on a normal 15 degrees off: its delta samples leave along
// wo mirrored about that normal, with weight clearcoat F_c(n_c . wo) over
// the probability of choosing the coat, chosen with that probability
// (binomial z-test).
TEST(ClearcoatNormal, SmoothCoatMirrorsAboutItsOwnNormal) {
    const glm::vec3 n = tilted(15);
    const shared::Material m = coated({0.6f, 0.05f, 0.05f}, 0.0f, 0.5f, 0.0f, n);
    const glm::vec3 wo = worldDirection(0.8, 0.0);
    const double c = glm::dot(n, wo);
    const double fresnel = 0.04 + 0.96 * std::pow(1 - c, 5.0);
    const glm::vec3 mirror = 2.0f * glm::dot(n, wo) * n - wo;
    const shared::Frame frame = shared::makeFrame(NORMAL);
    const shared::MetallicRoughness p = shared::materialMetallicRoughness(m, frame);
    const glm::vec3 o = shared::frameToLocal(frame, wo);
    const double pCoat = shared::layerChoice(p, o.z, glm::dot(p.coatNormal, o)).coat;
    const auto results = test::runBsdfDispatch(m, wo, NORMAL, 7, 200000);
    size_t delta = 0;
    for (const MicrofacetResult& r : results) {
        if (!(r.flags & 2u)) continue;
        ++delta;
        EXPECT_LT(glm::length(r.direction - mirror), 1e-5f);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.weight[k], fresnel / pCoat, 1e-4);
        if (testing::Test::HasFailure()) return;
    }
    const double count = double(results.size());
    const double z = (double(delta) - count * pCoat) / std::sqrt(count * pCoat * (1 - pCoat));
    EXPECT_LT(std::abs(z), Z_CRITICAL) << delta << " of " << count << ", expected p " << pCoat;
}

// White furnace: glTF's white metal (roughness 0.5, compensated to albedo 1
// with the conductor's integral at wo) under a smooth coat on a normal 10
// degrees off, wo near the normal so that the coat's mirror stays above the
// surface: the coat takes F_c at its own normal from the base and returns
// it whole, so the mean weight is 1 within the z-test's bound plus 3e-4
// (the integral's accuracy).
TEST(ClearcoatNormal, SmoothCoatOverWhiteMetalReturnsAllTheLight) {
    const float cosTheta = 0.9f;
    shared::Material m = coated(glm::vec3(1.0f), 1.0f, 0.5f, 0.0f, tilted(10));
    const double e = albedo::conductorAlbedo(cosTheta, 0.5f);
    m.multipleScattering = float((1 - e) / e);
    const test::MeanWeight w = test::meanWeight(
        test::runBsdfDispatch(m, worldDirection(cosTheta, 0.5), NORMAL, 11, SAMPLES));
    EXPECT_LT(std::abs(w.mean - 1.0), Z_CRITICAL * w.standardError + 3e-4)
        << "mean " << w.mean << ", standard error " << w.standardError;
}

}  // namespace
