// Materials as the kernels see them: one record per scene material.
#ifndef VKPATH_SHARED_MATERIAL_H
#define VKPATH_SHARED_MATERIAL_H

#include "shared/compat.h"
#include "shared/features.h"
#include "shared/records.h"
#include "shared/texture.h"

// Values of Material::kind, one per row of the registry
// (shared/material_kinds.h): VKP_MATERIAL_DIFFUSE, VKP_MATERIAL_MIRROR, ...
#define VKP_MATERIAL_CONSTANT(id, NAME, Type, key, label, feature, flags, regularized) \
    VKP_CONSTANT(VKP_MATERIAL_##NAME, id)
VKP_MATERIAL_KINDS(VKP_MATERIAL_CONSTANT)
#undef VKP_MATERIAL_CONSTANT

VKP_NAMESPACE_BEGIN

// Material::flags: a conductor with the exact Fresnel equations of a complex
// index (eta in `reflectance`, k in `transmittance`) instead of Schlick's.
#define VKP_MATERIAL_COMPLEX_FRESNEL 1u
// Material::flags: a conductor whose reflectance is `reflectance` at every
// angle (a mirror roughened by path regularisation, shared/bsdf.h).
#define VKP_MATERIAL_CONSTANT_FRESNEL 2u
// Material::flags: a glass (smooth or rough) whose surface is a thin wall
// with air on both sides (glTF's transmission without a volume): what passes
// leaves unbent, the reflection lobe mirrored through the surface
// (shared/lobes.h sampleThinDielectric, shared/microfacet.h).
#define VKP_MATERIAL_THIN_WALLED 4u

// Each field serves the kinds its comment names and is ignored by the others
// (176 bytes for every kind, eleven 16-byte texels: kernels read the array as
// a texel buffer and fetch only the texels their features read,
// stages/lib/scene_access.glsl; scene::Material has a field per meaning).
// Material's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_MATERIAL_FIELDS(F)                                                                   \
    /* diffuse: albedo; mirror, glass, rough glass: reflection tint; conductor: Schlick's F0, */ \
    /* or the complex index's real part eta; metallic-roughness: base colour */                  \
    F(vec3, reflectance, 0)                                                                      \
    /* VKP_MATERIAL_* */                                                                         \
    F(uint, kind, 3)                                                                             \
    /* glass, rough glass: tint of refracted light; conductor: the complex index's imaginary */  \
    /* part k; metallic-roughness: the dielectric layer's Fresnel at normal incidence (weight */ \
    /* included) */                                                                              \
    F(vec3, transmittance, 4)                                                                    \
    /* glass, rough glass: index of refraction of the inside relative to the outside */          \
    F(float, ior, 7)                                                                             \
    /* emitted radiance, W/(m^2 sr), from the front face */                                      \
    F(vec3, emission, 8)                                                                         \
    /* index of the first of its VKP_SLOTS_PER_MATERIAL TextureSlots (shared/texture.h), or */   \
    /* VKP_NO_TEXTURE */                                                                         \
    F(uint, textures, 11)                                                                        \
    /* conductor, rough glass, metallic-roughness: GGX alpha = roughness^2 */                    \
    F(float, roughness, 12)                                                                      \
    /* metallic-roughness: 0 dielectric, 1 metal */                                              \
    F(float, metallic, 13)                                                                       \
    /* metallic-roughness: the dielectric layer's weight, its Fresnel at grazing incidence */    \
    F(float, specular, 14)                                                                       \
    /* VKP_MATERIAL_COMPLEX_FRESNEL, VKP_MATERIAL_CONSTANT_FRESNEL, VKP_MATERIAL_THIN_WALLED */  \
    F(uint, flags, 15)                                                                           \
    /* glass, rough glass: absorption coefficient of the inside, per metre (Beer-Lambert; */     \
    /* KHR_materials_volume); 0: clear */                                                        \
    F(vec3, attenuation, 16)                                                                     \
    /* conductor, rough glass, metallic-roughness: multiple-scattering compensation's */         \
    /* (1 - E) / E at the hit's wo, set per hit (shared/path/energy_compensation.h); 0 in the */ \
    /* scene's array */                                                                          \
    F(float, multipleScattering, 19)                                                             \
    /* metallic-roughness: KHR_materials_sheen's colour (0: no sheen) and roughness */           \
    F(vec3, sheenColor, 20)                                                                      \
    F(float, sheenRoughness, 23)                                                                 \
    /* metallic-roughness: KHR_materials_clearcoat's weight (0: no coat) and roughness */        \
    F(float, clearcoat, 24)                                                                      \
    F(float, clearcoatRoughness, 25)                                                             \
    /* metallic-roughness: the white sheen lobe's albedo E_sheen(mu_o) at the hit's wo, set */   \
    /* per hit (shared/path/energy_compensation.h); 0 in the scene's array */                    \
    F(float, sheenLobeAlbedo, 26)                                                                \
    /* glass, rough glass with an inside: KHR_materials_dispersion's 20 / Abbe number (0: */     \
    /* the index is the same at every wavelength; shared/spectral.h) */                          \
    F(float, dispersion, 27)                                                                     \
    /* metallic-roughness: KHR_materials_diffuse_transmission's colour and share of the */       \
    /* diffuse lobe that passes to the back (0: none) */                                         \
    F(vec3, diffuseTransmissionColor, 28)                                                        \
    F(float, diffuseTransmission, 31)                                                            \
    /* metallic-roughness: KHR_materials_iridescence's weight (0: no film), the film's index */  \
    /* and its thickness in nm, from the minimum to the thickness (the maximum, until a */       \
    /* thickness texture picks between them per hit) */                                          \
    F(float, iridescence, 32)                                                                    \
    F(float, iridescenceIor, 33)                                                                 \
    F(float, iridescenceThicknessMinimum, 34)                                                    \
    F(float, iridescenceThickness, 35)                                                           \
    /* conductor, rough glass, metallic-roughness: KHR_materials_anisotropy's strength (0: */    \
    /* isotropic) and direction: in the scene's array the tangent frame's (cos, sin, 0) of */    \
    /* its rotation; per hit, after the texture, the unit world-space direction along which */   \
    /* the lobe is rougher (shared/path/shading_normals.h) */                                    \
    F(vec3, anisotropyDirection, 36)                                                             \
    F(float, anisotropy, 39)                                                                     \
    /* metallic-roughness: the clear coat's own normal at the hit (world space, unit, facing */  \
    /* wo: KHR_materials_clearcoat's clearcoatNormalTexture), set per hit; 0 where the coat */   \
    /* takes the shading normal, and in the scene's array */                                     \
    F(vec3, clearcoatNormal, 40)                                                                 \
    F(uint, padding, 43)
struct Material {
    VKP_MATERIAL_FIELDS(VKP_FIELD_DECLARE)
};

// The feature bit of material kind `kind` (shared/features.h).
VKP_FN FeatureMask materialFeature(uint kind) {
    switch (kind) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized) \
    case id:                                                                   \
        return feature;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            return VKP_NO_FEATURES;
    }
}

// The VKP_KIND_* flags of material kind `kind`.
VKP_FN uint materialKindFlags(uint kind) {
    switch (kind) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized) \
    case id:                                                                   \
        return flags;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            return 0u;
    }
}

// Whether the kernel may meet material kind `kind`. One case per kind, each
// asking hasFeature of its own bit, so that a kernel built for a feature
// profile without the kind has a constant false there (shared/features.h).
VKP_FN bool materialMayBe(uint kind) {
    switch (kind) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized) \
    case id:                                                                   \
        return hasFeature(feature);
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            return false;
    }
}

// material.kind, or the constant kind when the kernel meets only one (so a
// switch over it folds to that case).
VKP_FN uint materialKind(VKP_IN(Material) material) {
    for (uint kind = 0u; kind < VKP_MATERIAL_KIND_COUNT; ++kind)
        if (onlyFeature(VKP_FEATURES_MATERIALS, materialFeature(kind))) return kind;
    return material.kind;
}

// Whether `material` is of kind `kind`; known without reading it when the
// kernel meets no material of that kind, or no other.
VKP_FN bool materialIs(VKP_IN(Material) material, uint kind) {
    if (!materialMayBe(kind)) return false;
    if (onlyFeature(VKP_FEATURES_MATERIALS, materialFeature(kind))) return true;
    return material.kind == kind;
}

// Whether `material` is glass (a kind of VKP_KIND_TRANSMITS); known without
// reading it when the kernel meets no glass, or only glass.
VKP_FN bool materialTransmits(VKP_IN(Material) material) {
    if (!hasFeature(VKP_FEATURES_TRANSMITS)) return false;
    if (!hasFeature(VKP_FEATURES_MATERIALS & ~VKP_FEATURES_TRANSMITS)) return true;
    return (materialKindFlags(material.kind) & VKP_KIND_TRANSMITS) != 0u;
}

// Whether `material` (a glass) is a thin wall: no inside, no refraction.
VKP_FN bool materialThinWalled(VKP_IN(Material) material) {
    return hasFeature(VKP_FEATURE_THIN_WALLED) && (material.flags & VKP_MATERIAL_THIN_WALLED) != 0u;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD Material
VKP_RECORD_CHECK(VKP_MATERIAL_FIELDS, 11)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_MATERIAL_H
