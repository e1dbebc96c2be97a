// The microfacet albedo tables (shaders/shared/microfacet_albedo.h, written at
// build time by host/albedo/make_albedo_tables.cpp) and the
// multiple-scattering compensation built on them
// (shaders/shared/path/energy_compensation.h), on the CPU: the tables hold the
// integrals they claim, their interpolation between grid points stays within
// its stated error of direct integration, and the compensated white lobes,
// sampled through the BSDF dispatch as a path vertex samples them, return
// all the light at every roughness and angle. (The same on the GPU, in whole
// renders: tests/render/microfacet_render_test.cpp, MicrofacetFurnace.)
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <string>

#include "albedo/albedo_integrals.h"
#include "albedo/albedo_tables.h"
#include "shared/bsdf.h"
#include "shared/microfacet_albedo.h"

namespace vkpath::shared {

// energy_compensation.h's lookups over the built tables: the accessor it
// reads, and its functions as members (as the CPU reference's view has them).
struct AlbedoTableLookup {
    std::span<const float> table = albedo::microfacetAlbedoTable();
    float sceneMicrofacetAlbedo(uint index) const { return table[index]; }
#define VKP_SCENE_CONST const
#pragma push_macro("VKP_FN")
#undef VKP_FN
#define VKP_FN inline
#include "shared/path/energy_compensation.h"
#pragma pop_macro("VKP_FN")
#undef VKP_SCENE_CONST
};

}  // namespace vkpath::shared

namespace {

using namespace vkpath;

const shared::AlbedoTableLookup LOOKUP;

// A white material of `kind` (F0 1: Schlick's Fresnel is exactly 1; tints 1;
// glTF's white metal).
shared::Material whiteMaterial(uint32_t kind, float roughness, float ior = 1.5f) {
    shared::Material m{};
    m.kind = kind;
    m.reflectance = glm::vec3(1.0f);
    m.transmittance = glm::vec3(1.0f);
    m.roughness = roughness;
    m.ior = ior;
    m.metallic = 1.0f;
    m.specular = 1.0f;
    return m;
}

// wo at signed cosine c to the normal +z.
glm::vec3 outgoing(float c) {
    return glm::vec3(std::sqrt(std::max(0.0f, 1.0f - c * c)), 0.0f, c);
}

// The tables hold the integrals of albedo_integrals.h at their grid points:
// the generator's output equals the integral computed here (the same code and
// compiler flags; 1e-6 allows for a different evaluation order).
TEST(AlbedoTable, HoldsTheIntegralsAtItsGridPoints) {
    const std::span<const float> table = albedo::microfacetAlbedoTable();
    ASSERT_EQ(table.size(), VKP_ALBEDO_TABLE_SIZE);
    for (uint32_t r : {6u, 13u, 31u})
        for (uint32_t c : {1u, 9u, 31u}) {
            const float cosTheta = shared::albedoGridCos(c);
            const float roughness = shared::albedoGridRoughness(r);
            const uint32_t cell = r * VKP_ALBEDO_COS_COUNT + c;
            EXPECT_NEAR(table[VKP_ALBEDO_CONDUCTOR_OFFSET + cell],
                        albedo::conductorAlbedo(cosTheta, roughness), 1e-6);
            for (uint32_t n : {0u, 7u, 15u}) {
                const float eta = shared::albedoGridIor(n);
                const uint32_t at = n * VKP_ALBEDO_CONDUCTOR_SIZE + cell;
                EXPECT_NEAR(table[VKP_ALBEDO_ENTERING_OFFSET + at],
                            albedo::dielectricAlbedo(cosTheta, roughness, eta), 1e-6);
                EXPECT_NEAR(table[VKP_ALBEDO_LEAVING_OFFSET + at],
                            albedo::dielectricAlbedo(cosTheta, roughness, 1 / eta), 1e-6);
            }
            EXPECT_NEAR(table[VKP_ALBEDO_SHEEN_OFFSET + cell],
                        albedo::sheenAlbedo(cosTheta, roughness), 1e-6);
        }
    for (uint32_t i = 0; i < VKP_ALBEDO_SHEEN_OFFSET; ++i) {  // (the sheen's may be 0)
        ASSERT_GT(table[i], 0.0f);
        ASSERT_LE(table[i], 1.0f + 1e-6f);
    }
}

// The integrals themselves: 64 x 64 visible normals (albedo::GRID_SIDE)
// against 256 x 256, for the conductor and the glass from both sides, at
// roughness 0.1 to 1 and cos 0.01 to 1. Measured: conductor at most 2.2e-4,
// glass 3.5e-3 (light leaving glass of index 1.1 at roughness 1, where total
// internal reflection cuts across the visible normals); bounds 5e-4 and 5e-3.
TEST(AlbedoTable, IntegralsConverge) {
    double conductor = 0, glass = 0;
    for (float r : {0.1f, 0.3f, 0.6f, 1.0f})
        for (float c : {0.01f, 0.2f, 1.0f}) {
            conductor = std::max(conductor, std::abs(albedo::conductorAlbedo(c, r) -
                                                     albedo::conductorAlbedo(c, r, 256)));
            for (float eta : {1.5f, 1 / 1.5f, 1.1f, 1 / 1.1f})
                glass = std::max(glass, std::abs(albedo::dielectricAlbedo(c, r, eta) -
                                                 albedo::dielectricAlbedo(c, r, eta, 256)));
        }
    double sheen = 0;
    for (float r : {0.0f, 0.1f, 0.3f, 0.6f, 1.0f})
        for (float c : {0.01f, 0.2f, 1.0f})
            sheen =
                std::max(sheen, std::abs(albedo::sheenAlbedo(c, r) -
                                         albedo::sheenAlbedo(c, r, 4 * albedo::SHEEN_GRID_SIDE)));
    std::printf(
        "  largest difference from 256 x 256: conductor %.2e, glass %.2e; sheen from "
        "512 x 512: %.2e\n",
        conductor, glass, sheen);
    EXPECT_LT(conductor, 5e-4);
    EXPECT_LT(glass, 5e-3);
    EXPECT_LT(sheen, 1e-4);
}

// The sheen's albedo against the extension's formulas written out in double
// here (Estevez and Kulla's D and Lambda, KHR_materials_sheen's notes)
// and integrated another way: the midpoint rule in (theta_i, phi), 1024 x 256
// points over the hemisphere (phi over [0, pi], the lobe being symmetric
// about wo's plane). Agrees with the table's integral to 2e-4 (measured
// below). Every entry is finite and >= 0; above 1 only at grazing angles
// below roughness 0.3, the fit's excess (up to 6.12 as the roughness goes to
// 0), which the layered material scales away (shared/metallic_roughness.h).
double charlieLambda(double cosTheta, double alpha) {
    const double t = (1 - alpha) * (1 - alpha);
    const auto l = [&](double x) {
        const double a = 21.5473 + (25.3245 - 21.5473) * t, b = 3.82987 + (3.32435 - 3.82987) * t,
                     c = 0.19823 + (0.16801 - 0.19823) * t, d = -1.97760 + (-1.27393 + 1.97760) * t,
                     e = -4.32054 + (-4.85967 + 4.32054) * t;
        return a / (1 + b * std::pow(x, c)) + d * x + e;
    };
    return cosTheta < 0.5 ? std::exp(l(cosTheta)) : std::exp(2 * l(0.5) - l(1 - cosTheta));
}

double sheenAlbedoInDouble(double cosO, double roughness) {
    const double pi = 3.14159265358979323846;
    const double alpha = std::max(roughness * roughness, 1e-3);
    const glm::dvec3 o(std::sqrt(1 - cosO * cosO), 0, cosO);
    const int thetas = 1024, phis = 256;
    double sum = 0;
    for (int y = 0; y < thetas; ++y) {
        const double theta = (y + 0.5) / thetas * pi / 2;
        for (int x = 0; x < phis; ++x) {
            const double phi = (x + 0.5) / phis * pi;
            const glm::dvec3 i(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
            const glm::dvec3 h = glm::normalize(o + i);
            const double d = (2 + 1 / alpha) * std::pow(1 - h.z * h.z, 0.5 / alpha) / (2 * pi);
            const double f =
                d / (4 * o.z * i.z * (1 + charlieLambda(o.z, alpha) + charlieLambda(i.z, alpha)));
            sum += f * i.z * std::sin(theta);
        }
    }
    return 2 * sum * (pi / 2 / thetas) * (pi / phis);
}

TEST(AlbedoTable, SheenAlbedoIsTheExtensionsIntegral) {
    double worst = 0;
    for (float r : {0.0f, 0.2f, 0.5f, 1.0f})
        for (float c : {0.05f, 0.3f, 0.7f, 1.0f})
            worst =
                std::max(worst, std::abs(albedo::sheenAlbedo(c, r) - sheenAlbedoInDouble(c, r)));
    std::printf("  largest difference from the double-precision integral: %.2e\n", worst);
    EXPECT_LT(worst, 2e-4);
    const std::span<const float> table = albedo::microfacetAlbedoTable();
    float largest = 0;
    for (uint32_t i = VKP_ALBEDO_SHEEN_OFFSET; i < VKP_ALBEDO_TABLE_SIZE; ++i) {
        ASSERT_TRUE(std::isfinite(table[i]));
        ASSERT_GE(table[i], 0.0f);
        const uint32_t cell = i - VKP_ALBEDO_SHEEN_OFFSET;
        if (shared::albedoGridRoughness(cell / VKP_ALBEDO_COS_COUNT) >= 0.3f ||
            shared::albedoGridCos(cell % VKP_ALBEDO_COS_COUNT) >= 0.2f) {
            EXPECT_LE(table[i], 1.0f) << "roughness index " << cell / VKP_ALBEDO_COS_COUNT
                                      << ", cos index " << cell % VKP_ALBEDO_COS_COUNT;
        }
        largest = std::max(largest, table[i]);
    }
    std::printf("  the largest entry: %.2f\n", largest);
}

// Between the grid points, where linear interpolation is furthest from the
// truth: each cell's centre on every axis (midway in the square root of cos,
// roughness and x = (eta - 1) / (eta + 1), the axes' spacing), against the
// integral there, as the relative error of the compensated albedo
// E / E_interpolated - 1. Cells of cos theta_o >= 0.01 and non-delta
// roughness; the glass at the cells around indices 1.33 (water), 1.5 and 2.4
// (diamond), both sides; the sheen at every other cell of both axes.
// Measured: conductor and glass 0.0076 (bound 0.01), sheen as below.
TEST(AlbedoTable, InterpolationStaysNearTheIntegral) {
    const auto midway = [](uint32_t i, uint32_t count) {
        const float s = (float(i) + 0.5f) / float(count - 1u);
        return s * s;
    };
    double conductor = 0, glass = 0;
    for (uint32_t r = 0; r + 1 < VKP_ALBEDO_ROUGHNESS_COUNT; ++r) {
        const float roughness = midway(r, VKP_ALBEDO_ROUGHNESS_COUNT);
        if (shared::microfacetIsSmooth(glm::vec2(roughness * roughness))) continue;
        for (uint32_t c = 0; c + 1 < VKP_ALBEDO_COS_COUNT; ++c) {
            const float cosTheta = midway(c, VKP_ALBEDO_COS_COUNT);
            if (cosTheta < 0.01f) continue;
            const shared::Material metal = whiteMaterial(VKP_MATERIAL_CONDUCTOR, roughness);
            conductor = std::max(conductor, std::abs(albedo::conductorAlbedo(cosTheta, roughness) /
                                                         LOOKUP.microfacetAlbedo(metal, cosTheta) -
                                                     1));
            if (r % 3 != 0 || c % 3 != 0) continue;  // the glass's cells: a ninth of them
            for (float x : {0.1416f, 0.2f, 0.4155f}) {
                const uint32_t n = uint32_t(std::sqrt(x / VKP_ALBEDO_IOR_X_MAX) *
                                            float(VKP_ALBEDO_IOR_COUNT - 1u));
                const float xMid = VKP_ALBEDO_IOR_X_MAX * midway(n, VKP_ALBEDO_IOR_COUNT);
                const float ior = (1 + xMid) / (1 - xMid);
                const shared::Material rough =
                    whiteMaterial(VKP_MATERIAL_ROUGH_DIELECTRIC, roughness, ior);
                for (float side : {1.0f, -1.0f}) {
                    const double e =
                        albedo::dielectricAlbedo(cosTheta, roughness, side > 0 ? ior : 1 / ior);
                    glass = std::max(
                        glass, std::abs(e / LOOKUP.microfacetAlbedo(rough, side * cosTheta) - 1));
                }
            }
        }
    }
    // The sheen's, in what the layered material reads of it: min(1, E), an
    // absolute error (the base keeps 1 - min(1, E)), and max(1, E), relative
    // (the lobe is divided by it).
    double sheen = 0;
    for (uint32_t r = 0; r + 1 < VKP_ALBEDO_ROUGHNESS_COUNT; r += 2)
        for (uint32_t c = 0; c + 1 < VKP_ALBEDO_COS_COUNT; c += 2) {
            const float roughness = midway(r, VKP_ALBEDO_ROUGHNESS_COUNT);
            const float cosTheta = midway(c, VKP_ALBEDO_COS_COUNT);
            shared::Material m = whiteMaterial(VKP_MATERIAL_METALLIC_ROUGHNESS, 0.5f);
            m.sheenColor = glm::vec3(1.0f);
            m.sheenRoughness = roughness;
            const double e = albedo::sheenAlbedo(cosTheta, roughness);
            const double interpolated = LOOKUP.sheenLobeAlbedo(m, cosTheta);
            const double error =
                std::max(std::abs(std::min(1.0, e) - std::min(1.0, interpolated)),
                         std::abs(std::max(1.0, e) / std::max(1.0, interpolated) - 1));
            sheen = std::max(sheen, error);
        }
    std::printf(
        "  largest relative error between grid points: conductor %.4f, glass %.4f; "
        "sheen %.4f\n",
        conductor, glass, sheen);
    EXPECT_LT(conductor, 0.01);
    EXPECT_LT(glass, 0.01);
    // The sheen's worst cell is its narrowest lobe's (roughness -> 0, the
    // alpha floor) at cos 0.044, where E falls from 6 to 0 between cos 0 and
    // 0.1: 0.0276 there; bound 0.03.
    EXPECT_LT(sheen, 0.03);
}

// White furnace of the compensated lobes as a path vertex samples them:
// multipleScattering at wo, then sampleBsdf; the mean flux weight (weight x
// etaSquared; 5 x 10^4 samples of std::mt19937) is 1 within 5 standard errors +
// 1% (the tables' error, above) for the conductor, glTF's metal and the rough
// glass from outside and inside, at roughness 0.05 to 1 and cos theta_o 1 to
// 0.03; every sample's weight equals its evalBsdf / bsdfPdf (1e-4), so light
// samples see the same lobe. Without compensation the same lobes return
// E < 1 (the power: at roughness 1 the mean is below the bound).
TEST(CompensatedLobes, WhiteFurnaceReturnsAllTheLight) {
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    double worst = 0;
    std::string worstCase;
    for (uint32_t kind :
         {VKP_MATERIAL_CONDUCTOR, VKP_MATERIAL_METALLIC_ROUGHNESS, VKP_MATERIAL_ROUGH_DIELECTRIC})
        for (float roughness : {0.05f, 0.1f, 0.3f, 0.5f, 0.7f, 0.85f, 1.0f})
            for (float c : {1.0f, 0.7f, 0.4f, 0.1f, 0.03f})
                for (float side : {1.0f, -1.0f}) {
                    if (side < 0 && kind != VKP_MATERIAL_ROUGH_DIELECTRIC) continue;
                    SCOPED_TRACE(testing::Message() << "kind " << kind << " roughness " << roughness
                                                    << " cos " << side * c);
                    const glm::vec3 wo = outgoing(side * c);
                    const shared::Material single = whiteMaterial(kind, roughness);
                    shared::Material m = single;
                    m.multipleScattering = LOOKUP.multipleScattering(single, wo.z);
                    ASSERT_GE(m.multipleScattering, 0.0f);
                    if (roughness >= 0.3f) {
                        ASSERT_GT(m.multipleScattering, 0.0f);
                    }
                    const int count = 50000;
                    double sum = 0, sum2 = 0, singleSum = 0;
                    for (int i = 0; i < count; ++i) {
                        const glm::vec2 u(uniform(rng), uniform(rng));
                        const float uc = uniform(rng);
                        const shared::BsdfSample s = shared::sampleBsdf(m, n, n, wo, u, uc);
                        const shared::BsdfSample s1 = shared::sampleBsdf(single, n, n, wo, u, uc);
                        if (s1.valid) singleSum += s1.weight.x * s1.etaSquared;
                        if (!s.valid) continue;
                        const double w = s.weight.x * s.etaSquared;
                        sum += w;
                        sum2 += w * w;
                        if (i % 64 == 0) {
                            const float pdf = shared::bsdfPdf(m, n, n, wo, s.direction);
                            const glm::vec3 f = shared::evalBsdf(m, n, n, wo, s.direction);
                            ASSERT_NEAR(f.x / pdf, s.weight.x, 1e-4f * s.weight.x);
                        }
                    }
                    const double mean = sum / count;
                    const double standardError =
                        std::sqrt(std::max(0.0, sum2 / count - mean * mean) / count);
                    EXPECT_NEAR(mean, 1.0, 5 * standardError + 0.01);
                    if (std::abs(mean - 1) > worst) {
                        worst = std::abs(mean - 1);
                        worstCase = fmt::format("kind {} roughness {} cos {}: {:.4f} +- {:.4f}",
                                                kind, roughness, side * c, mean, standardError);
                    }
                    if (roughness == 1.0f) {
                        EXPECT_LT(singleSum / count, 1.0 - 5 * standardError - 0.01);
                    }
                }
    std::printf("  largest |mean - 1|: %s\n", worstCase.c_str());
}

}  // namespace
