// The directional albedos of the single-scattering GGX lobes with Fresnel 1
// (shaders/shared/microfacet_albedo.h says what they are for), integrated
// from the lobes' own code: the mean weight of visible-normal samples on a
// stratified grid of the unit square (midpoints of its cells). The build
// writes the tables from these (make_albedo_tables.cpp); the tests check the
// tables' interpolation against them between the grid points.
#pragma once
#include <glm/glm.hpp>

#include "shared/lobes.h"
#include "shared/microfacet.h"
#include "shared/sheen.h"

namespace vkpath::albedo {

// Samples per side of the stratified grid: 64 x 64 visible normals per albedo.
// Against 256 x 256 the conductor's albedos agree to 2.2e-4 and the
// dielectric's to 3.5e-3, where total internal reflection cuts across the
// visible normals (tests/kernels/albedo_table_test.cpp, IntegralsConverge);
// the whole table takes 3 s on two cores.
inline constexpr int GRID_SIDE = 64;

// wo at cosine cosTheta (> 0) to the normal, in the xz plane.
inline glm::vec3 outgoing(float cosTheta) {
    const float c = glm::clamp(cosTheta, 1e-4f, 1.0f);
    return glm::vec3(std::sqrt(std::max(0.0f, 1.0f - c * c)), 0.0f, c);
}

// The mean of weight(o, m) over the visible normals m of wo at cosine
// cosTheta, on a side x side grid: u.x the cells' midpoints, u.y = 1 - t^2
// with t the cells' midpoints, weighed by that substitution's density 2 t.
// Near u.y = 1, the rim of the spherical cap (shared::sampleGgxVisibleNormal),
// the normals turn from the lobe to grazing within a strip of width ~alpha:
// the substitution puts the grid's points there.
template <typename Weight>
double visibleNormalMean(float cosTheta, glm::vec2 alpha, int side, Weight weight) {
    const glm::vec3 o = outgoing(cosTheta);
    double sum = 0.0;
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const float t = (y + 0.5f) / side;
            const glm::vec2 u((x + 0.5f) / side, 1.0f - t * t);
            const glm::vec3 m = shared::sampleGgxVisibleNormal(o, alpha, u);
            if (glm::dot(o, m) > 0.0f) sum += 2.0 * t * weight(o, m);
        }
    return sum / (double(side) * side);
}

// E(mu_o, alpha) of the rough conductor with F = 1: the mean of
// G2 / G1(wo), the weight of shared::sampleConductor, over its samples
// (0 where the reflection goes below the surface).
inline double conductorAlbedo(float cosTheta, float roughness, int side = GRID_SIDE) {
    const glm::vec2 alpha(roughness * roughness);
    if (shared::microfacetIsSmooth(alpha)) return 1.0;
    return visibleNormalMean(cosTheta, alpha, side, [&](glm::vec3 o, glm::vec3 m) {
        const glm::vec3 i = 2.0f * glm::dot(o, m) * m - o;
        return i.z > 0.0f ? double(shared::ggxG2OverG1(o, i, alpha)) : 0.0;
    });
}

// E(mu_o, alpha, eta) of the white rough dielectric, eta the relative index
// of wi's side over wo's (> 1 entering, < 1 leaving): the flux albedo, the
// mean over visible normals of F G2 / G1 for the reflection and
// (1 - F) G2 / G1 for the refraction (shared::sampleRoughDielectric's
// weight times etaSquared), the choice between them taken in expectation.
inline double dielectricAlbedo(float cosTheta, float roughness, float eta, int side = GRID_SIDE) {
    const glm::vec2 alpha(roughness * roughness);
    if (shared::microfacetIsSmooth(alpha)) return 1.0;
    return visibleNormalMean(cosTheta, alpha, side, [&](glm::vec3 o, glm::vec3 m) {
        const float om = glm::dot(o, m);
        const float fresnel = shared::fresnelDielectric(om, eta);
        const glm::vec3 r = 2.0f * om * m - o;
        double weight = r.z > 0.0f ? fresnel * shared::ggxG2OverG1(o, r, alpha) : 0.0f;
        if (fresnel >= 1.0f) return weight;
        // Snell's law about m, as sampleRoughDielectric.
        const float sin2T = (1.0f - om * om) / (eta * eta);
        const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
        const glm::vec3 w = glm::normalize(-o / eta + (om / eta - cosT) * m);
        if (w.z < 0.0f) weight += (1.0f - fresnel) * shared::ggxG2OverG1(o, w, alpha);
        return weight;
    });
}

// Points per side of the sheen's grid: 128 x 128 directions per albedo
// (against 512 x 512 the entries agree to 1e-4: tests/kernels/
// albedo_table_test.cpp, IntegralsConverge).
inline constexpr int SHEEN_GRID_SIDE = 128;

// E_sheen(mu_o, roughness) of the white sheen lobe (shared/sheen.h): the
// integral of its f |cos theta_i| over the hemisphere, by the midpoint rule
// in (t, phi) with cos theta_i = t^2 (d omega = 2 t dt dphi), which crowds
// the points toward the horizon, where the lobe lies.
inline double sheenAlbedo(float cosTheta, float roughness, int side = SHEEN_GRID_SIDE) {
    const glm::vec3 o = outgoing(cosTheta);
    const float alpha = shared::sheenAlpha(roughness);
    const double twoPi = 6.283185307179586;
    double sum = 0.0;
    for (int y = 0; y < side; ++y) {
        const float t = (y + 0.5f) / side;
        const float cosI = t * t;
        const float sinI = std::sqrt(std::max(0.0f, 1.0f - cosI * cosI));
        for (int x = 0; x < side; ++x) {
            const float phi = float(twoPi) * (x + 0.5f) / side;
            const glm::vec3 i(sinI * std::cos(phi), sinI * std::sin(phi), cosI);
            sum += 2.0 * t * double(shared::sheenReflection(o, i, alpha));
        }
    }
    return sum * twoPi / (double(side) * side);
}

}  // namespace vkpath::albedo
