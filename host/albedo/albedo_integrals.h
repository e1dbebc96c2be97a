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

// The visible-normal sampler's u for cell (x, t): u.x = the cell's midpoint,
// u.y = 1 - t^2, whose density 2 t the integrals weigh by. Near u.y = 1, the
// rim of the spherical cap (shared::sampleGgxVisibleNormal), the normals turn
// from the lobe to grazing within a strip of width ~alpha; the substitution
// puts the grid's points there.
inline glm::vec2 gridPoint(int x, float t, int side) {
    return glm::vec2((x + 0.5f) / side, 1.0f - t * t);
}

// E(mu_o, alpha) of the rough conductor with F = 1: the mean of
// G2 / G1(wo), the weight of shared::sampleConductor, over its samples
// (0 where the reflection goes below the surface).
inline double conductorAlbedo(float cosTheta, float roughness, int side = GRID_SIDE) {
    const glm::vec2 alpha(roughness * roughness);
    if (shared::microfacetIsSmooth(alpha)) return 1.0;
    const glm::vec3 o = outgoing(cosTheta);
    double sum = 0.0;
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const float t = (y + 0.5f) / side;
            const glm::vec3 m = shared::sampleGgxVisibleNormal(o, alpha, gridPoint(x, t, side));
            const float om = glm::dot(o, m);
            const glm::vec3 i = 2.0f * om * m - o;
            if (om > 0.0f && i.z > 0.0f) sum += 2.0f * t * shared::ggxG2OverG1(o, i, alpha);
        }
    return sum / (double(side) * side);
}

// E(mu_o, alpha, eta) of the white rough dielectric, eta the relative index
// of wi's side over wo's (> 1 entering, < 1 leaving): the flux albedo, the
// mean over visible normals of F G2 / G1 for the reflection and
// (1 - F) G2 / G1 for the refraction (shared::sampleRoughDielectric's
// weight times etaSquared), the choice between them taken in expectation.
inline double dielectricAlbedo(float cosTheta, float roughness, float eta, int side = GRID_SIDE) {
    const glm::vec2 alpha(roughness * roughness);
    if (shared::microfacetIsSmooth(alpha)) return 1.0;
    const glm::vec3 o = outgoing(cosTheta);
    double sum = 0.0;
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const float t = (y + 0.5f) / side;
            const glm::vec3 m = shared::sampleGgxVisibleNormal(o, alpha, gridPoint(x, t, side));
            const float om = glm::dot(o, m);
            if (om <= 0.0f) continue;
            const float fresnel = shared::fresnelDielectric(om, eta);
            const glm::vec3 r = 2.0f * om * m - o;
            if (r.z > 0.0f) sum += 2.0f * t * fresnel * shared::ggxG2OverG1(o, r, alpha);
            if (fresnel >= 1.0f) continue;
            // Snell's law about m, as sampleRoughDielectric.
            const float sin2T = (1.0f - om * om) / (eta * eta);
            const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
            const glm::vec3 w = glm::normalize(-o / eta + (om / eta - cosT) * m);
            if (w.z < 0.0f) sum += 2.0f * t * (1.0f - fresnel) * shared::ggxG2OverG1(o, w, alpha);
        }
    return sum / (double(side) * side);
}

}  // namespace vkpath::albedo
