// The directional albedo of the single-scattering GGX lobes (shared/microfacet.h)
// and the multiple-scattering compensation built on it.
//
// A microfacet lobe reflects (or refracts) light once off the microsurface;
// light that meets the microsurface again is dropped, so a white rough
// conductor returns only E(mu_o) < 1 of the light (its furnace in
// docs/ACCURACY.md: 0.57 at alpha 1, cos theta_o 0.1) and rough glass darkens.
// Turquin 2019, "Practical multiple scattering compensation for microfacet
// models" (the scheme Cycles' multiscatter GGX uses) scales the lobe by
// 1 + F0 (1 - E(mu_o)) / E(mu_o), E the albedo of the lobe with Fresnel 1:
// with F0 = 1 the lobe then returns exactly 1, and the added energy follows
// the lobe's own shape, so sampling, pdfs and MIS are unchanged and only
// weights and evaluations scale. For the dielectric E is the flux albedo of
// the white lobe (reflection and transmission, whose Fresnel split conserves
// energy), and the factor is 1 / E: a white rough glass returns all of it.
// The factor depends on wo alone, so the compensated f is not reciprocal (as
// Turquin's and Cycles'); the lobes themselves are unchanged (the
// uncompensated ones are `render --single-scattering`, what Mitsuba 3 and
// pbrt-v4 render).
//
// The tables hold E, integrated at build time from the lobes' own sampling
// code (host/albedo/make_albedo_tables.cpp, with the integrals of
// host/albedo/albedo_integrals.h), on a grid of cos theta_o, roughness
// (alpha = roughness^2) and, for the dielectric, x = (eta - 1) / (eta + 1)
// of the relative index eta >= 1 on wo's side (an index below 1, light
// leaving the glass, has a table of its own, indexed by 1 / eta). Lookups
// interpolate linearly on each axis (tests/kernels/albedo_table_test.cpp
// measures the interpolation against direct integration between the grid
// points).
//
// One float array, read by the kernels as a scene array (shared/scene_arrays.h
// microfacetAlbedo) and by the CPU reference from the same table:
//
//   [conductor: ROUGHNESS x COS] [glass entering: IOR x ROUGHNESS x COS]
//   [glass leaving: IOR x ROUGHNESS x COS] [sheen: ROUGHNESS x COS]
//
// The last block is the white sheen lobe's albedo (shared/sheen.h, its
// roughness axis KHR_materials_sheen's sheenRoughness), which the sheen's
// albedo scaling reads (shared/metallic_roughness.h), compensation or not.
//
// cos fastest. This header has the layout and the grid's coordinates; the
// lookups, which read the array through the scene accessor
// sceneMicrofacetAlbedo(index), are shared/path/energy_compensation.h.
#ifndef VKPATH_SHARED_MICROFACET_ALBEDO_H
#define VKPATH_SHARED_MICROFACET_ALBEDO_H

#include "shared/compat.h"

#define VKP_ALBEDO_COS_COUNT 32u
#define VKP_ALBEDO_ROUGHNESS_COUNT 32u
#define VKP_ALBEDO_IOR_COUNT 16u
// The largest x = (eta - 1) / (eta + 1) of the dielectric's tables: eta 3,
// beyond every transparent material's index (diamond 2.42, rutile 2.9);
// larger ones take its value.
#define VKP_ALBEDO_IOR_X_MAX 0.5f

#define VKP_ALBEDO_CONDUCTOR_OFFSET 0u
#define VKP_ALBEDO_CONDUCTOR_SIZE (VKP_ALBEDO_ROUGHNESS_COUNT * VKP_ALBEDO_COS_COUNT)
#define VKP_ALBEDO_GLASS_SIZE \
    (VKP_ALBEDO_IOR_COUNT * VKP_ALBEDO_ROUGHNESS_COUNT * VKP_ALBEDO_COS_COUNT)
#define VKP_ALBEDO_ENTERING_OFFSET VKP_ALBEDO_CONDUCTOR_SIZE
#define VKP_ALBEDO_LEAVING_OFFSET (VKP_ALBEDO_ENTERING_OFFSET + VKP_ALBEDO_GLASS_SIZE)
#define VKP_ALBEDO_SHEEN_OFFSET (VKP_ALBEDO_LEAVING_OFFSET + VKP_ALBEDO_GLASS_SIZE)
#define VKP_ALBEDO_TABLE_SIZE (VKP_ALBEDO_SHEEN_OFFSET + VKP_ALBEDO_CONDUCTOR_SIZE)

VKP_NAMESPACE_BEGIN

// The grid's coordinates: point i of an axis and, for a value, its
// position in units of points (in [0, count - 1]). Each axis is uniform in
// the square root of its value, which puts its points where E changes
// fastest: at grazing angles, at low roughness (where the drop toward grazing
// narrows) and near index 1 (tests/kernels/albedo_table_test.cpp has the
// interpolation errors each spacing gives).
VKP_FN float albedoGridSquare(uint i, uint count) {
    float s = float(i) / float(count - 1u);
    return s * s;
}
VKP_FN float albedoGridPosition(float value, uint count) {
    return sqrt(clamp(value, 0.0f, 1.0f)) * float(count - 1u);
}
VKP_FN float albedoGridCos(uint i) {
    return albedoGridSquare(i, VKP_ALBEDO_COS_COUNT);
}
VKP_FN float albedoGridCosPosition(float cosTheta) {
    return albedoGridPosition(cosTheta, VKP_ALBEDO_COS_COUNT);
}
VKP_FN float albedoGridRoughness(uint i) {
    return albedoGridSquare(i, VKP_ALBEDO_ROUGHNESS_COUNT);
}
VKP_FN float albedoGridRoughnessPosition(float roughness) {
    return albedoGridPosition(roughness, VKP_ALBEDO_ROUGHNESS_COUNT);
}
// The relative index eta >= 1 of point i of the dielectric's index axis.
VKP_FN float albedoGridIor(uint i) {
    float x = VKP_ALBEDO_IOR_X_MAX * albedoGridSquare(i, VKP_ALBEDO_IOR_COUNT);
    return (1.0f + x) / (1.0f - x);
}
VKP_FN float albedoGridIorPosition(float eta) {
    return albedoGridPosition((eta - 1.0f) / ((eta + 1.0f) * VKP_ALBEDO_IOR_X_MAX),
                              VKP_ALBEDO_IOR_COUNT);
}

// A position split into the lower grid point and the weight of the upper one.
struct AlbedoGridCell {
    uint index;
    float weight;
};
VKP_FN AlbedoGridCell albedoGridCell(float position, uint count) {
    AlbedoGridCell c;
    c.index = min(uint(position), count - 2u);
    c.weight = position - float(c.index);
    return c;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_MICROFACET_ALBEDO_H
