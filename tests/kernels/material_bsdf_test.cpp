// The microfacet material kinds through shared/bsdf.h's dispatch (sampleBsdf,
// evalBsdf, bsdfPdf in the shading frame, world space), sampled on the GPU by
// tests/kernels/bsdf_dispatch.comp with the path tracer's random numbers:
// glTF's metallic-roughness material follows its mixture density (chi-square,
// 10^6 samples each, 1% Sidak-corrected over the file's statistical tests),
// every non-delta sample of every new kind has weight f |cos| / pdf through
// the dispatch, the layered material is reciprocal, and its smooth limit is a
// delta specular lobe beside the diffuse one. The lobes themselves are
// microfacet_test.cpp's. Materials are made by the host's own conversion
// (wavefront::buildSceneTables), so scene::Material's fields are what is tested.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "albedo/albedo_integrals.h"
#include "image/statistics.h"
#include "kernels/bsdf_dispatch.h"
#include "kernels/microfacet_routines.h"
#include "scene/scene.h"
#include "shared/bsdf.h"
#include "support/bsdf_dispatch_run.h"
#include "support/direction_chi2.h"
#include "support/fresnel_rounding.h"
#include "support/test_context.h"
#include "support/test_scenes.h"
#include "vk/buffer.h"
#include "vk/kernel.h"
#include "wavefront/gpu_scene.h"

namespace {

using namespace vkpath;
using shared::MicrofacetResult;
using test::gpuMaterial;

constexpr uint32_t SAMPLES = 1000000;
constexpr double PI = 3.14159265358979323846;
// Statistical tests in this file: chi-square of the layered material 8;
// binomial z-tests of its smooth limit's lobe choice 2; chi-square of the
// coats, sheens, diffuse transmission and thin films 10, the smooth coat's lobe choice 1,
// their furnaces 7;
// chi-square of the rough thin walls 3, their furnace 1, the smooth thin
// wall's choice 1.
constexpr int STATISTICAL_TESTS = 33;
const double ALPHA = test::sidakAlpha(0.01, STATISTICAL_TESTS);
const double Z_CRITICAL = image::normalCritical(ALPHA);

scene::Material metallicRoughness(glm::vec3 base, float metallic, float roughness) {
    scene::Material m;
    m.kind = scene::MaterialKind::MetallicRoughness;
    m.reflectance = base;
    m.metallic = metallic;
    m.roughness = roughness;
    return m;
}

const glm::vec3 NORMAL = test::DISPATCH_NORMAL;

// The world direction at cosine cosTheta to NORMAL, azimuth phi in its frame.
glm::vec3 worldDirection(double cosTheta, double phi = 0.4) {
    return test::directionInFrame(shared::makeFrame(NORMAL), cosTheta, phi);
}

std::vector<MicrofacetResult> runDispatch(const shared::Material& material, glm::vec3 wo,
                                          uint32_t seed = 1, uint32_t count = SAMPLES) {
    return test::runBsdfDispatch(material, wo, NORMAL, seed, count);
}

// ---- the layered material's density, written from the papers in double ------------
// GGX (Walter et al. 2007, eq. 33) and Smith's G1 (Heitz 2014) for an
// isotropic alpha; the visible-normal density D_wo(h) = G1(wo) max(0, wo.h)
// D(h) / wo.z (Heitz 2018) and the reflection Jacobian 1 / (4 wo.h) (Walter
// eq. 14); the cosine density i.z / pi. Only the lobe probability is the
// header's (specularProbability: the sampler's choice, whose value any
// density would have to take).

double ggxD(glm::dvec3 m, double alpha) {
    if (m.z <= 0) return 0;
    const double tan2 = (m.x * m.x + m.y * m.y) / (m.z * m.z);
    const double c4 = m.z * m.z * m.z * m.z;
    return 1 /
           (PI * alpha * alpha * c4 * (1 + tan2 / (alpha * alpha)) * (1 + tan2 / (alpha * alpha)));
}

double smithG1(glm::dvec3 w, double alpha) {
    const double tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
    return 2 / (1 + std::sqrt(1 + alpha * alpha * tan2));
}

// The density of wi (world) given wo (world) for the layered material; with
// diffuse transmission the cosine lobe's mirror image below the surface
// takes the header's share of the diffuse samples (diffuseTransmissionProbability).
double layeredDensity(const shared::Material& m, glm::vec3 wo, glm::vec3 wi) {
    const shared::Frame frame = shared::makeFrame(NORMAL);
    glm::dvec3 o(shared::frameToLocal(frame, wo)), i(shared::frameToLocal(frame, wi));
    if (o.z < 0) {
        o = -o;
        i = -i;
    }
    const shared::MetallicRoughness p = shared::materialMetallicRoughness(m);
    const double pSpec = shared::specularProbability(p, float(o.z));
    const double pass = shared::diffuseTransmissionProbability(p);
    if (i.z < 0) return (1 - pSpec) * pass * -i.z / PI;
    if (i.z == 0) return 0;
    const double alpha = double(m.roughness) * m.roughness;
    const glm::dvec3 h = glm::normalize(o + i);
    const double oh = glm::dot(o, h);
    const double visible = oh > 0 ? smithG1(o, alpha) * oh * ggxD(h, alpha) / o.z : 0;
    return pSpec * visible / (4 * oh) + (1 - pSpec) * (1 - pass) * i.z / PI;
}

struct LayeredCase {
    const char* name;
    scene::Material material;
    double cosTheta;  // of wo with the normal; < 0: from below (two-sided)
};

std::vector<LayeredCase> layeredCases() {
    scene::Material specular = metallicRoughness({0.3f, 0.6f, 0.2f}, 0.0f, 0.45f);
    specular.specular = 0.6f;
    specular.specularColor = {1.0f, 0.4f, 0.1f};
    specular.ior = 1.8f;
    return {
        {"plastic", metallicRoughness({0.8f, 0.3f, 0.1f}, 0.0f, 0.5f), 0.8},
        {"glossy plastic at normal incidence", metallicRoughness({0.2f, 0.2f, 0.7f}, 0.0f, 0.3f),
         1.0},
        {"half metal", metallicRoughness({0.9f, 0.6f, 0.3f}, 0.5f, 0.4f), 0.3},
        {"metal", metallicRoughness({0.95f, 0.64f, 0.54f}, 1.0f, 0.6f), 0.9},
        {"grazing", metallicRoughness({0.5f, 0.5f, 0.5f}, 0.2f, 0.7f), 0.05},
        {"from below", metallicRoughness({0.7f, 0.7f, 0.2f}, 0.3f, 0.5f), -0.6},
        {"rough white plastic", metallicRoughness(glm::vec3(1.0f), 0.0f, 1.0f), 0.5},
        {"specular colour and weight, ior 1.8", specular, 0.7},
    };
}

// Samples through the dispatch follow the mixture of the GGX visible-normal
// reflection and the cosine lobe, each weighted by the lobe probability at
// wo (chi-square on the whole sphere, samples reflected below the surface
// their own cell); each sample's pdf equals the test's to 1e-3 relative; the
// mixture integrates to at most 1 (less by the specular lobe's losses).
TEST(MetallicRoughness, SamplesFollowTheMixtureDensity) {
    const auto cases = layeredCases();
    ASSERT_EQ(int(cases.size()), 8);
    for (const LayeredCase& c : cases) {
        SCOPED_TRACE(c.name);
        const shared::Material m = gpuMaterial(c.material);
        const glm::vec3 wo = worldDirection(c.cosTheta);
        const auto results = runDispatch(m, wo, 7);
        test::DirectionGrid grid;
        grid.frame = shared::makeFrame(NORMAL);
        const double alpha = double(c.material.roughness) * c.material.roughness;
        grid.polarExponent = alpha <= 0.1 ? 2 : 1;
        auto pdf = [&](glm::vec3 wi) { return layeredDensity(m, wo, wi); };
        std::vector<glm::vec3> valid;
        double worstPdf = 0;
        for (const MicrofacetResult& r : results) {
            if (!(r.flags & 1u)) continue;
            EXPECT_EQ(r.flags & 2u, 0u) << "a rough lobe's sample marked delta";
            valid.push_back(r.direction);
            worstPdf = std::max(worstPdf, std::abs(r.pdf / pdf(r.direction) - 1));
        }
        EXPECT_LT(worstPdf, 1e-3) << "sample pdf against the test's density";
        EXPECT_LE(test::integrateOverSphere(grid, pdf), 1.0 + 1e-3);
        const auto result =
            test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(), pdf);
        EXPECT_GT(result.pValue, ALPHA)
            << "chi2 " << result.statistic << ", dof " << result.degreesOfFreedom;
    }
}

// Power: the same samples judged against the mixture with the lobe
// probability moved by 0.05 (too much of the specular lobe), and against the
// cosine lobe alone, are rejected.
TEST(MetallicRoughness, ChiSquareRejectsAWrongMixture) {
    const scene::Material material = metallicRoughness({0.8f, 0.3f, 0.1f}, 0.3f, 0.5f);
    const shared::Material m = gpuMaterial(material);
    const glm::vec3 wo = worldDirection(0.7);
    const auto results = runDispatch(m, wo, 11);
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(NORMAL);
    std::vector<glm::vec3> valid;
    for (const MicrofacetResult& r : results)
        if (r.flags & 1u) valid.push_back(r.direction);
    const size_t lost = results.size() - valid.size();
    const shared::Frame frame = shared::makeFrame(NORMAL);
    const double pSpec = shared::specularProbability(shared::materialMetallicRoughness(m), 0.7f);
    auto shifted = [&](glm::vec3 wi) {
        const double cosine = std::max(0.0, double(shared::frameToLocal(frame, wi).z)) / PI;
        const double right = layeredDensity(m, wo, wi);
        const double specular = (right - (1 - pSpec) * cosine) / pSpec;
        return (pSpec + 0.05) * specular + (1 - pSpec - 0.05) * cosine;
    };
    EXPECT_LT(test::chiSquareDirectionsWithLosses(grid, valid, lost, shifted).pValue, 1e-10);
    auto cosineOnly = [&](glm::vec3 wi) {
        return std::max(0.0, double(shared::frameToLocal(frame, wi).z)) / PI;
    };
    EXPECT_LT(test::chiSquareDirectionsWithLosses(grid, valid, lost, cosineOnly).pValue, 1e-10);
}

// ---- f |cos| / pdf = weight through the dispatch ----------------------------------------

struct WeightCase {
    const char* name;
    scene::Material material;
    double cosTheta;
};

std::vector<WeightCase> weightCases() {
    auto conductor = [](glm::vec3 f0, float roughness) {
        scene::Material m;
        m.kind = scene::MaterialKind::Conductor;
        m.reflectance = f0;
        m.roughness = roughness;
        return m;
    };
    scene::Material gold = conductor(glm::vec3(1.0f), 0.4f);
    gold.conductorEta = {0.18f, 0.42f,
                         1.37f};  // gold at 650, 550, 450 nm (Johnson and Christy 1972)
    gold.conductorK = {3.42f, 2.35f, 1.77f};
    auto roughGlass = [](float ior, float roughness) {
        scene::Material m;
        m.kind = scene::MaterialKind::RoughDielectric;
        m.ior = ior;
        m.roughness = roughness;
        m.reflectance = glm::vec3(1.0f);
        m.transmittance = {0.9f, 0.8f, 0.7f};
        return m;
    };
    scene::Material smooth = metallicRoughness({0.6f, 0.3f, 0.2f}, 0.3f, 0.0f);
    return {
        {"conductor, Schlick", conductor({0.95f, 0.64f, 0.54f}, 0.5f), 0.6},
        {"conductor, complex index of gold", gold, 0.8},
        {"conductor, from below", conductor({0.9f, 0.9f, 0.9f}, 0.3f), -0.4},
        {"rough glass from outside", roughGlass(1.5f, 0.4f), 0.7},
        {"rough glass from inside", roughGlass(1.5f, 0.6f), -0.9},
        {"rough glass 1.33, narrow", roughGlass(1.33f, 0.2f), 0.4},
        {"metallic-roughness", metallicRoughness({0.8f, 0.3f, 0.1f}, 0.4f, 0.5f), 0.5},
        {"metallic-roughness, grazing", metallicRoughness({0.5f, 0.9f, 0.5f}, 0.0f, 0.8f), 0.1},
        {"metallic-roughness, smooth (delta layer)", smooth, 0.6},
    };
}

// The rough glass's Fresnel has an infinite slope at the critical angle
// (1 - F grows like sqrt(cos - cos_c)): there a change of wo.m by its
// rounding (bounded by 1e-6, as in microfacet_test.cpp) changes F, or 1 - F
// for transmission, by this relative amount; elsewhere it is ~1e-6.
double fresnelRounding(const shared::Material& material, glm::vec3 worldWo, glm::vec3 worldWi) {
    if (material.kind != VKP_MATERIAL_ROUGH_DIELECTRIC) return 0;
    const shared::Frame frame = shared::makeFrame(NORMAL);
    const glm::vec3 wo = shared::frameToLocal(frame, worldWo),
                    wi = shared::frameToLocal(frame, worldWi);
    return test::fresnelRounding(material.ior, wo, wi);
}

// Every valid non-delta sample's weight equals the dispatch's own
// evalBsdf / bsdfPdf at the sampled direction (GPU), and bsdfPdf equals the
// sample's pdf. The sample computes f and pdf at its local direction, the
// evaluation at that direction after its round trip through the world frame
// (frameToWorld, normalize, frameToLocal), which moves the direction by float
// rounding, ~1e-7. Near the horizon the ratios f / pdf of a mixture or a
// Fresnel-weighted lobe change relative to cos theta_i, and a narrow lobe's D
// changes by up to 2 / alpha relative per radian the half vector moves (more
// for refraction, whose half vector wo + eta wi is shorter). So the bound is
// 1e-5 + 1e-7 / |cos theta_i| + 4e-6 / alpha relative (measured: at most
// 3.8e-6 where |cos theta_i| > 0.05 and alpha >= 0.09; near the horizon the
// error times |cos theta_i| is at most 6e-8; refraction at alpha 0.04 at most
// 1.0e-6 / alpha), plus for the rough glass the relative change of its
// Fresnel term by rounding (fresnelRounding). Where transmission is sampled,
// etaSquared is the ratio of the indices squared, else 1.
TEST(MaterialDispatch, WeightIsEvalOverPdf) {
    for (const WeightCase& c : weightCases()) {
        SCOPED_TRACE(c.name);
        const shared::Material m = gpuMaterial(c.material);
        const glm::vec3 wo = worldDirection(c.cosTheta);
        const auto results = runDispatch(m, wo, 5, 200000);
        const double alpha = double(c.material.roughness) * c.material.roughness;
        double worst = 0;  // the largest error over its bound
        size_t nonDelta = 0;
        for (const MicrofacetResult& r : results) {
            if (!(r.flags & 1u) || (r.flags & 2u)) continue;
            ++nonDelta;
            ASSERT_GT(r.evalPdf, 0.0f);
            const double cosI = std::abs(glm::dot(r.direction, NORMAL));
            const double bound =
                1e-5 + 1e-7 / cosI + 4e-6 / alpha + fresnelRounding(m, wo, r.direction);
            worst = std::max(worst, std::abs(double(r.evalPdf) / r.pdf - 1) / bound);
            const glm::vec3 expected = r.eval / r.evalPdf;
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, std::abs(double(r.weight[k]) - expected[k]) /
                                            std::max(1e-6, std::abs(double(expected[k]))) / bound);
            const bool transmitted = glm::dot(r.direction, NORMAL) * c.cosTheta < 0;
            if (transmitted) {
                const float eta = c.cosTheta > 0 ? c.material.ior : 1.0f / c.material.ior;
                EXPECT_NEAR(r.etaSquared, eta * eta, 1e-5f * eta * eta);
            } else {
                EXPECT_EQ(r.etaSquared, 1.0f);
            }
        }
        EXPECT_GT(nonDelta, 1000u);
        EXPECT_LT(worst, 1.0) << "the worst error, in units of its bound";
    }
}

// f(wo, wi) = f(wi, wo) for the layered material (f = evalBsdf / |cos wi|,
// C++): its diffuse part's Fresnel weight and its GGX lobe depend on wo and wi
// only through the half vector and both cosines symmetrically. 20000 random
// pairs on either side, random parameters; 1e-5 relative (float rounding:
// the two evaluations differ in the order of operations).
TEST(MetallicRoughness, Reciprocity) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto randomDirection = [&]() {
        const float z = 2 * u(rng) - 1, phi = float(2 * PI) * u(rng);
        const float r = std::sqrt(std::max(0.0f, 1 - z * z));
        return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    int compared = 0;
    for (int n = 0; n < 20000; ++n) {
        scene::Material sm = metallicRoughness({u(rng), u(rng), u(rng)}, u(rng), 0.05f + u(rng));
        sm.specular = u(rng);
        sm.specularColor = {u(rng), u(rng), u(rng)};
        const shared::Material m = gpuMaterial(sm);
        const glm::vec3 wo = randomDirection(), wi = randomDirection();
        const float co = std::abs(glm::dot(wo, NORMAL)), ci = std::abs(glm::dot(wi, NORMAL));
        if (co < 1e-3f || ci < 1e-3f) continue;
        const glm::vec3 f1 = shared::evalBsdf(m, NORMAL, NORMAL, wo, wi) / ci;
        const glm::vec3 f2 = shared::evalBsdf(m, NORMAL, NORMAL, wi, wo) / co;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(f1[k], f2[k], 1e-5f * std::max(f1[k], 1e-3f));
        compared += f1 != glm::vec3(0.0f);
        if (testing::Test::HasFailure()) return;
    }
    EXPECT_GT(compared, 5000);
}

// Roughness below the smooth threshold: the specular lobe is a delta. The
// dispatch picks it with probability specularProbability (binomial z-test),
// in exactly the mirror direction, pdf that probability, weight the Fresnel
// terms at wo.n over it (to 1e-5 of the C++ value); the other samples are the
// diffuse lobe's, whose eval and pdf the dispatch's functions return (the
// delta direction's too: the delta has no density to add). At roughness 0.03
// (alpha 9e-4) and 0.
TEST(MetallicRoughness, SmoothLayerIsADeltaBesideTheDiffuseLobe) {
    for (float roughness : {0.0f, 0.03f}) {
        SCOPED_TRACE(testing::Message() << "roughness " << roughness);
        const shared::Material m =
            gpuMaterial(metallicRoughness({0.6f, 0.3f, 0.2f}, 0.3f, roughness));
        const float cosTheta = 0.6f;
        const glm::vec3 wo = worldDirection(cosTheta);
        const shared::MetallicRoughness p = shared::materialMetallicRoughness(m);
        const double pSpec = shared::specularProbability(p, cosTheta);
        const glm::vec3 weight =
            shared::metallicRoughnessSpecularFresnel(p, cosTheta) / float(pSpec);
        const glm::vec3 mirror = shared::reflectAbout(wo, NORMAL);
        const auto results = runDispatch(m, wo, 9, 200000);
        size_t delta = 0;
        for (const MicrofacetResult& r : results) {
            ASSERT_TRUE(r.flags & 1u);
            if (r.flags & 2u) {
                ++delta;
                EXPECT_LT(glm::length(r.direction - mirror), 1e-5f);
                EXPECT_NEAR(r.pdf, pSpec, 1e-6);
                for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.weight[k], weight[k], 1e-5f * weight[k]);
            } else {
                EXPECT_NEAR(r.evalPdf / r.pdf, 1.0f, 1e-4f);
                EXPECT_NEAR(r.pdf, (1 - pSpec) * glm::dot(r.direction, NORMAL) / PI, 1e-4 * r.pdf);
            }
            if (testing::Test::HasFailure()) return;
        }
        const double n = double(results.size());
        const double z = (double(delta) - n * pSpec) / std::sqrt(n * pSpec * (1 - pSpec));
        EXPECT_LT(std::abs(z), Z_CRITICAL)
            << delta << " delta samples of " << n << ", expected p " << pSpec;
    }
}

}  // namespace

// ---- the layers: clear coat and sheen (KHR_materials_clearcoat, KHR_materials_sheen) --------

// A metallic-roughness material under a coat of weight `coat` and roughness
// `coatRoughness` and a sheen of colour `sheen` and roughness
// `sheenRoughness`, with the sheen's albedo at wo (cosine cosTheta) set as a
// path vertex sets it (from the integral the table holds at grid points).
shared::Material layeredMaterial(scene::Material base, float coat, float coatRoughness,
                                 glm::vec3 sheen, float sheenRoughness, double cosTheta) {
    base.clearcoat = coat;
    base.clearcoatRoughness = coatRoughness;
    base.sheenColor = sheen;
    base.sheenRoughness = sheenRoughness;
    shared::Material m = gpuMaterial(base);
    if (sheen != glm::vec3(0.0f))
        m.sheenLobeAlbedo = float(albedo::sheenAlbedo(float(std::abs(cosTheta)), sheenRoughness));
    return m;
}

// The density of wi given wo for the layered material: the coat's GGX
// visible-normal reflection, the sheen's uniform hemisphere and the base's
// mixture (layeredDensity), each weighted by its layer's probability at wo
// (the header's layerChoice: the sampler's choice, as specularProbability
// above).
double coatAndSheenDensity(const shared::Material& m, glm::vec3 wo, glm::vec3 wi) {
    const shared::Frame frame = shared::makeFrame(NORMAL);
    glm::dvec3 o(shared::frameToLocal(frame, wo)), i(shared::frameToLocal(frame, wi));
    if (o.z < 0) {
        o = -o;
        i = -i;
    }
    const shared::LayerChoice c =
        shared::layerChoice(shared::materialMetallicRoughness(m), float(o.z));
    if (i.z <= 0) return c.base * layeredDensity(m, wo, wi);  // (what passes: the base's)
    double coat = 0;
    if (m.clearcoat > 0) {
        const double alpha = double(m.clearcoatRoughness) * m.clearcoatRoughness;
        const glm::dvec3 h = glm::normalize(o + i);
        const double oh = glm::dot(o, h);
        coat = oh > 0 ? smithG1(o, alpha) * ggxD(h, alpha) / (4 * o.z) : 0;
    }
    return c.coat * coat + c.sheen / (2 * PI) + c.base * layeredDensity(m, wo, wi);
}

// What a run of non-delta samples says against a density `pdf`: the valid
// directions (for the chi-square), the worst sample pdf against the density
// (relative), and the worst weight against the dispatch's own evalBsdf /
// bsdfPdf in units of WeightIsEvalOverPdf's bound for a narrowest GGX
// alpha `alpha`.
struct SampleCheck {
    std::vector<glm::vec3> valid;
    double worstPdf = 0;
    double worstWeight = 0;
};

template <typename Pdf>
SampleCheck checkSamples(const std::vector<MicrofacetResult>& results, const Pdf& pdf,
                         double alpha) {
    SampleCheck check;
    for (const MicrofacetResult& r : results) {
        if (!(r.flags & 1u)) continue;
        EXPECT_EQ(r.flags & 2u, 0u) << "a rough lobe's sample marked delta";
        check.valid.push_back(r.direction);
        check.worstPdf = std::max(check.worstPdf, std::abs(r.pdf / pdf(r.direction) - 1));
        const double bound = 1e-5 + 1e-7 / std::abs(glm::dot(r.direction, NORMAL)) + 4e-6 / alpha;
        const glm::vec3 expected = r.eval / r.evalPdf;
        for (int k = 0; k < 3; ++k)
            check.worstWeight =
                std::max(check.worstWeight, std::abs(double(r.weight[k]) - expected[k]) /
                                                std::max(1e-6, double(expected[k])) / bound);
    }
    EXPECT_LT(check.worstPdf, 1e-3) << "sample pdf against the test's density";
    EXPECT_LT(check.worstWeight, 1.0) << "the worst weight error, in units of its bound";
    return check;
}

// The chi-square test of the valid samples of `total` against `pdf` on the
// whole sphere (the lost ones their own cell), which integrates to at most 1.
template <typename Pdf>
void expectChiSquareFits(const std::vector<glm::vec3>& valid, size_t total, const Pdf& pdf) {
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(NORMAL);
    EXPECT_LE(test::integrateOverSphere(grid, pdf), 1.0 + 1e-3);
    const auto result = test::chiSquareDirectionsWithLosses(grid, valid, total - valid.size(), pdf);
    EXPECT_GT(result.pValue, ALPHA)
        << "chi2 " << result.statistic << ", dof " << result.degreesOfFreedom;
}

// That the mean weight of `results` (invalid samples 0: the material's
// albedo at wo) is `expected` within the z-test's bound of its standard
// error plus `accuracy`.
void expectMeanWeight(const std::vector<MicrofacetResult>& results, double expected,
                      double accuracy) {
    const test::MeanWeight w = test::meanWeight(results);
    EXPECT_LT(std::abs(w.mean - expected), Z_CRITICAL * w.standardError + accuracy)
        << "mean " << w.mean << ", expected " << expected << ", standard error " << w.standardError;
}

struct LayerCase {
    const char* name;
    shared::Material material;
    double cosTheta;
};

// `m` under a thin film of index 1.3 and `thickness` nm (KHR_materials_iridescence).
scene::Material film(scene::Material m, float thickness) {
    m.iridescence = 1.0f;
    m.iridescenceIor = 1.3f;
    m.iridescenceThicknessMaximum = thickness;
    return m;
}

// A green non-metal (roughness 0.5) whose diffuse lobe passes `share` of
// its light to the back, tinted yellow (KHR_materials_diffuse_transmission).
scene::Material leaf(float share) {
    scene::Material m = metallicRoughness({0.1f, 0.5f, 0.1f}, 0.0f, 0.5f);
    m.diffuseTransmission = share;
    m.diffuseTransmissionColor = {0.8f, 0.9f, 0.2f};
    return m;
}

std::vector<LayerCase> layerCases() {
    const glm::vec3 pink(1.0f, 0.55f, 0.6f);
    const scene::Material plastic = metallicRoughness({0.6f, 0.05f, 0.05f}, 0.0f, 0.5f);
    const scene::Material gold = metallicRoughness({1.0f, 0.77f, 0.34f}, 1.0f, 0.4f);
    const scene::Material cloth = metallicRoughness({0.3f, 0.02f, 0.04f}, 0.0f, 0.9f);
    return {
        {"rough coat over plastic", layeredMaterial(plastic, 1.0f, 0.3f, {}, 0, 0.8), 0.8},
        {"half a coat over gold, grazing", layeredMaterial(gold, 0.5f, 0.6f, {}, 0, 0.15), 0.15},
        {"sheen over cloth", layeredMaterial(cloth, 0, 0, pink, 0.4f, 0.6), 0.6},
        {"narrow sheen, from below", layeredMaterial(cloth, 0, 0, pink, 0.2f, 0.5), -0.5},
        {"coat and sheen", layeredMaterial(plastic, 0.8f, 0.2f, pink, 0.7f, 0.4), 0.4},
        {"half the diffuse passes", layeredMaterial(leaf(0.5f), 0, 0, {}, 0, 0.7), 0.7},
        {"all the diffuse passes, from below", layeredMaterial(leaf(1.0f), 0, 0, {}, 0, -0.6),
         -0.6},
        {"a coat over a leaf", layeredMaterial(leaf(0.4f), 0.6f, 0.3f, {}, 0, 0.5), 0.5},
        {"a thin film on plastic", layeredMaterial(film(plastic, 300.0f), 0, 0, {}, 0, 0.6), 0.6},
        {"a thin film on silver, grazing",
         layeredMaterial(film(metallicRoughness(glm::vec3(0.9f), 1.0f, 0.3f), 400.0f), 0, 0, {}, 0,
                         0.2),
         0.2},
    };
}

// Samples through the dispatch follow the layers' mixture (chi-square on the
// whole sphere, as the base's above), each sample's pdf is the density's to
// 1e-3, and every sample's weight is the dispatch's own evalBsdf / bsdfPdf
// (the base's bound of WeightIsEvalOverPdf, 1e-5 + 1e-7 / |cos theta_i| +
// 4e-6 / alpha of the narrower GGX lobe).
TEST(MaterialLayers, SamplesFollowTheirDensity) {
    for (const LayerCase& c : layerCases()) {
        SCOPED_TRACE(c.name);
        const glm::vec3 wo = worldDirection(c.cosTheta);
        const auto results = runDispatch(c.material, wo, 13);
        auto pdf = [&](glm::vec3 wi) { return coatAndSheenDensity(c.material, wo, wi); };
        const double alpha = std::min(
            c.material.roughness * c.material.roughness,
            c.material.clearcoat > 0 ? c.material.clearcoatRoughness * c.material.clearcoatRoughness
                                     : 1.0f);
        expectChiSquareFits(checkSamples(results, pdf, alpha).valid, results.size(), pdf);
    }
}

// Power: the coat-and-sheen case's samples judged against the mixture with
// the sheen's uniform lobe taken for the cosine lobe are rejected.
TEST(MaterialLayers, ChiSquareRejectsACosineSheen) {
    const LayerCase c = layerCases().at(4);  // coat and sheen
    const glm::vec3 wo = worldDirection(c.cosTheta);
    const auto results = runDispatch(c.material, wo, 17);
    test::DirectionGrid grid;
    grid.frame = shared::makeFrame(NORMAL);
    std::vector<glm::vec3> valid;
    for (const MicrofacetResult& r : results)
        if (r.flags & 1u) valid.push_back(r.direction);
    const shared::LayerChoice choice =
        shared::layerChoice(shared::materialMetallicRoughness(c.material), float(c.cosTheta));
    auto wrong = [&](glm::vec3 wi) {
        const double z = std::max(0.0, double(glm::dot(wi, NORMAL)));
        return coatAndSheenDensity(c.material, wo, wi) +
               choice.sheen * (z / PI - (z > 0 ? 1 / (2 * PI) : 0));
    };
    EXPECT_LT(test::chiSquareDirectionsWithLosses(grid, valid, results.size() - valid.size(), wrong)
                  .pValue,
              1e-10);
}

// A smooth coat (roughness 0) is a delta: picked with the layer choice's
// probability (binomial z-test), in the mirror direction, weight clearcoat
// F_c(cos theta_o) over that probability; the other samples are the base's
// and the sheen's, with the dispatch's eval and pdf.
TEST(MaterialLayers, SmoothCoatIsADelta) {
    const float cosTheta = 0.5f;
    const shared::Material m = layeredMaterial(metallicRoughness({0.6f, 0.05f, 0.05f}, 0.0f, 0.5f),
                                               1.0f, 0.0f, {}, 0, cosTheta);
    const glm::vec3 wo = worldDirection(cosTheta);
    const shared::MetallicRoughness p = shared::materialMetallicRoughness(m);
    const double pCoat = shared::layerChoice(p, cosTheta).coat;
    const double fresnel = 0.04 + 0.96 * std::pow(1.0 - cosTheta, 5.0);
    const glm::vec3 mirror = shared::reflectAbout(wo, NORMAL);
    const auto results = runDispatch(m, wo, 19, 200000);
    size_t delta = 0;
    for (const MicrofacetResult& r : results) {
        if (!(r.flags & 1u)) continue;
        if (r.flags & 2u) {
            ++delta;
            EXPECT_LT(glm::length(r.direction - mirror), 1e-5f);
            EXPECT_NEAR(r.pdf, pCoat, 1e-6);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.weight[k], fresnel / pCoat, 1e-5);
        } else {
            EXPECT_NEAR(r.evalPdf / r.pdf, 1.0f, 1e-4f);
        }
        if (testing::Test::HasFailure()) return;
    }
    const double n = double(results.size());
    const double z = (double(delta) - n * pCoat) / std::sqrt(n * pCoat * (1 - pCoat));
    EXPECT_LT(std::abs(z), Z_CRITICAL)
        << delta << " delta samples of " << n << ", expected p " << pCoat;
}

// White furnace: the layers over glTF's white metal (metallic 1, base colour
// 1, roughness 0.5), compensated to albedo exactly 1 with the conductor's
// integral at wo (albedo::conductorAlbedo, accurate to 2.2e-4:
// tests/kernels/albedo_table_test.cpp). The mean weight of 10^6 samples is
// the material's albedo: a white sheen takes max(sheenColor) min(1, E_sheen)
// and leaves the base 1 - that, so the sum stays 1; a coat of weight w returns
// its lobe's albedo E_coat in place of the base's 1 for the share w F_c
// (E_coat the conductor's integral at the coat's roughness; 1 when smooth).
// Judged by a z-test with the samples' own standard error, plus 3e-4 for the
// integrals' accuracy.
TEST(MaterialLayers, WhiteFurnaceReturnsWhatTheCoatKeeps) {
    struct Case {
        const char* name;
        float coat, coatRoughness, sheenRoughness;
        double cosTheta;
    };
    const Case cases[] = {
        {"rough coat", 1.0f, 0.3f, 0.0f, 0.7},
        {"rough coat, grazing", 1.0f, 0.5f, 0.0f, 0.2},
        {"smooth coat", 1.0f, 0.0f, 0.0f, 0.5},
        {"white sheen", 0.0f, 0.0f, 0.5f, 0.6},
        {"narrow white sheen, grazing (its lobe's albedo above 1)", 0.0f, 0.0f, 0.1f, 0.05},
        {"half a coat over a white sheen", 0.5f, 0.4f, 0.3f, 0.3},
        {"a coat over white diffuse transmission", 1.0f, 0.3f, 0.0f, 0.5},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const glm::vec3 sheen = c.sheenRoughness > 0 ? glm::vec3(1.0f) : glm::vec3(0.0f);
        // The last case's base: a white non-metal without a specular layer
        // whose diffuse lobe passes 0.6 of its light (albedo 1 with both sides).
        const bool passes = &c == &cases[std::size(cases) - 1];
        scene::Material base = metallicRoughness(glm::vec3(1.0f), passes ? 0.0f : 1.0f, 0.5f);
        if (passes) {
            base.specular = 0.0f;
            base.diffuseTransmission = 0.6f;
        }
        shared::Material m =
            layeredMaterial(base, c.coat, c.coatRoughness, sheen, c.sheenRoughness, c.cosTheta);
        const double baseAlbedo = albedo::conductorAlbedo(float(c.cosTheta), 0.5f);
        if (!passes) m.multipleScattering = float((1 - baseAlbedo) / baseAlbedo);
        const double coatAlbedo =
            c.coatRoughness > 0 ? albedo::conductorAlbedo(float(c.cosTheta), c.coatRoughness) : 1;
        const double fc = c.coat * (0.04 + 0.96 * std::pow(1 - c.cosTheta, 5.0));
        const double expected = 1 - fc * (1 - coatAlbedo);
        expectMeanWeight(runDispatch(m, worldDirection(c.cosTheta), 23), expected, 3e-4);
    }
}

// ---- thin walls: glTF's transmission without a volume -------------------------------------

scene::Material thinWall(float roughness, glm::vec3 tint = glm::vec3(1.0f)) {
    scene::Material m;
    m.kind = roughness > 0 ? scene::MaterialKind::RoughDielectric : scene::MaterialKind::Dielectric;
    m.roughness = roughness;
    m.ior = 1.5f;
    m.reflectance = glm::vec3(1.0f);
    m.transmittance = tint;
    m.thinWalled = true;
    return m;
}

// The rough thin wall's density, written here in double: the GGX
// visible-normal reflection of wo (ggxD, smithG1 above), its mirror image
// through the surface for what passes, F or 1 - F of each (the exact
// dielectric Fresnel at index 1.5 from either side, lobes.h's, evaluated in
// double by the textbook formula).
double fresnelDouble(double cosI, double eta) {
    const double sin2T = (1 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1) return 1;
    const double cosT = std::sqrt(1 - sin2T);
    const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5 * (rs * rs + rp * rp);
}

double thinWallDensity(const shared::Material& m, glm::vec3 wo, glm::vec3 wi) {
    const shared::Frame frame = shared::makeFrame(NORMAL);
    glm::dvec3 o(shared::frameToLocal(frame, wo)), i(shared::frameToLocal(frame, wi));
    if (o.z < 0) {
        o = -o;
        i = -i;
    }
    const glm::dvec3 r(i.x, i.y, std::abs(i.z));
    const double alpha = double(m.roughness) * m.roughness;
    const glm::dvec3 h = glm::normalize(o + r);
    const double f = fresnelDouble(glm::dot(o, h), m.ior);
    return (i.z > 0 ? f : 1 - f) * smithG1(o, alpha) * ggxD(h, alpha) / (4 * o.z);
}

// Samples of the rough thin wall follow that density (chi-square on the
// whole sphere), each sample's pdf is the density's to 1e-3, what passes
// keeps etaSquared 1, and every weight is the dispatch's evalBsdf / bsdfPdf
// (the bound of WeightIsEvalOverPdf). From outside, from behind and near
// grazing.
TEST(ThinWall, SamplesFollowTheirDensity) {
    const struct {
        const char* name;
        float roughness;
        double cosTheta;
    } cases[] = {{"from outside", 0.4f, 0.7}, {"from behind", 0.3f, -0.5}, {"grazing", 0.6f, 0.1}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        const shared::Material m = gpuMaterial(thinWall(c.roughness, {0.9f, 0.7f, 0.5f}));
        const glm::vec3 wo = worldDirection(c.cosTheta);
        const auto results = runDispatch(m, wo, 29);
        auto pdf = [&](glm::vec3 wi) { return thinWallDensity(m, wo, wi); };
        const SampleCheck check = checkSamples(results, pdf, double(c.roughness) * c.roughness);
        size_t passed = 0;
        for (const MicrofacetResult& r : results) {
            if (!(r.flags & 1u)) continue;
            ASSERT_EQ(r.etaSquared, 1.0f);
            passed += glm::dot(r.direction, NORMAL) * c.cosTheta < 0;
        }
        EXPECT_GT(passed, check.valid.size() / 2) << "most of the light passes";
        expectChiSquareFits(check.valid, results.size(), pdf);
    }
}

// White furnace of the rough thin wall (roughness 0.5, cos 0.4), compensated
// with the conductor's integral at wo (its lobe is the conductor's, split
// between the two sides): the mean weight of 10^6 samples is 1 within the
// z-test's bound + 3e-4 (the integral's accuracy).
TEST(ThinWall, WhiteFurnaceReturnsAllTheLight) {
    shared::Material m = gpuMaterial(thinWall(0.5f));
    const double e = albedo::conductorAlbedo(0.4f, 0.5f);
    m.multipleScattering = float((1 - e) / e);
    expectMeanWeight(runDispatch(m, worldDirection(0.4), 31), 1.0, 3e-4);
}

// The smooth thin wall reflects with the Fresnel probability at index 1.5
// (binomial z-test), weight 1 (reflectance 1); what passes leaves along -wo
// exactly, weight the tint, etaSquared 1.
TEST(ThinWall, SmoothWallPassesLightUnbent) {
    const glm::vec3 tint(0.9f, 0.7f, 0.5f);
    const shared::Material m = gpuMaterial(thinWall(0.0f, tint));
    const double cosTheta = 0.6;
    const glm::vec3 wo = worldDirection(cosTheta);
    const double f = fresnelDouble(cosTheta, 1.5);
    const auto results = runDispatch(m, wo, 37, 200000);
    size_t reflected = 0;
    for (const MicrofacetResult& r : results) {
        ASSERT_EQ(r.flags, 3u) << "valid deltas";
        ASSERT_EQ(r.etaSquared, 1.0f);
        if (glm::dot(r.direction, NORMAL) > 0) {
            ++reflected;
            EXPECT_EQ(r.weight, glm::vec3(1.0f));
        } else {
            EXPECT_EQ(r.direction, -wo);
            EXPECT_EQ(r.weight, tint);
        }
        if (testing::Test::HasFailure()) return;
    }
    const double n = double(results.size());
    const double z = (double(reflected) - n * f) / std::sqrt(n * f * (1 - f));
    EXPECT_LT(std::abs(z), Z_CRITICAL) << reflected << " reflected of " << n << ", F " << f;
}
