// The registry of material kinds: the one list of them, read by GLSL and C++.
// Everything that depends on the set of kinds comes from this list: the
// VKP_MATERIAL_* numbers (shared/material.h), scene::MaterialKind
// (host/scene/scene.h), the feature masks (shared/features.h), the dispatch
// switches over a material's BSDF (shared/bsdf.h), the names in scene-info
// and the logs, and the host's switches (a switch over scene::MaterialKind
// has no default, so -Wswitch names every place a new kind must be handled:
// the Mitsuba export). tests/kernels/material_registry_test.cpp walks it.
//
// One row per kind:
//
//   X(ID, NAME, Type, key, "label", FEATURE, FLAGS, REGULARIZED)
//
//   ID           Material::kind, 0 to VKP_MATERIAL_KIND_COUNT - 1 in order
//   NAME         VKP_MATERIAL_NAME, the kernels' constant
//   Type         scene::MaterialKind::Type, and the stem of the kind's
//                function set in shared/bsdf.h: sampleTypeMaterial,
//                evalTypeMaterial, pdfTypeMaterial, nonDeltaTypeMaterial,
//                regularizeTypeMaterial
//   key          the kind's key in scene-info's JSON and scene::FeatureSummary
//   "label"      its name in scene-info's text and in the kernels' feature list
//   FEATURE      its feature bit (shared/features.h), VKP_FEATURE_NAME: kernels
//                without it compile none of its code. The kinds' bits are
//                among the other features' (the first free one for a new kind:
//                kernel_features.cpp static_asserts that every bit is named once)
//   FLAGS        VKP_KIND_* below
//   REGULARIZED  the NAME of the kind path regularisation turns it into
//                (regularizeTypeMaterial returns that kind; itself if it only
//                roughens or stays)
//
// Adding a kind: a row here (the next ID and a free feature bit), its
// function set in shared/bsdf.h (its lobes beside
// those of shared/lobes.h or shared/microfacet.h), the importers that produce
// it, and its case in the Mitsuba export (the compiler asks for it).
// docs/ARCHITECTURE.md, "Adding a material kind", is the checklist.
#ifndef VKPATH_SHARED_MATERIAL_KINDS_H
#define VKPATH_SHARED_MATERIAL_KINDS_H

// FLAGS: what the kernels and the host may assume of a kind without reading
// its parameters.
#define VKP_KIND_NON_DELTA 1u  // may have a non-delta lobe: light sampling can reach it
#define VKP_KIND_MICROFACET \
    2u  // a GGX lobe of Material::roughness (and the metallic-roughness texture)
#define VKP_KIND_TRANSMITS \
    4u  // glass: refracts into a closed inside (absorption, the base colour tints
        // Material::transmittance)
#define VKP_KIND_LOBE_CHOICE 8u  // sampleTypeMaterial reads its own number uc to choose a lobe

#define VKP_MATERIAL_KINDS(X)                                                                     \
    /* Lambertian of albedo reflectance */                                                        \
    X(0u, DIFFUSE, Diffuse, diffuse, "diffuse", VKP_FEATURE_BIT(2), VKP_KIND_NON_DELTA, DIFFUSE)  \
    /* perfect specular reflection scaled by reflectance */                                       \
    X(1u, MIRROR, Mirror, mirror, "mirror", VKP_FEATURE_BIT(3), 0u, CONDUCTOR)                    \
    /* smooth glass: exact Fresnel between index 1 and ior, tinted by reflectance and             \
     * transmittance */                                                                           \
    X(2u, DIELECTRIC, Dielectric, glass, "glass", VKP_FEATURE_BIT(4), VKP_KIND_TRANSMITS,         \
      ROUGH_DIELECTRIC)                                                                           \
    /* GGX reflection of roughness (shared/microfacet.h): Schlick's Fresnel of F0 reflectance, or \
       the exact Fresnel of a complex index */                                                    \
    X(3u, CONDUCTOR, Conductor, conductor, "conductor", VKP_FEATURE_BIT(20),                      \
      VKP_KIND_NON_DELTA | VKP_KIND_MICROFACET, CONDUCTOR)                                        \
    /* GGX reflection and refraction of roughness between index 1 and ior (Walter et al. 2007) */ \
    X(4u, ROUGH_DIELECTRIC, RoughDielectric, roughGlass, "rough-glass", VKP_FEATURE_BIT(21),      \
      VKP_KIND_NON_DELTA | VKP_KIND_MICROFACET | VKP_KIND_TRANSMITS | VKP_KIND_LOBE_CHOICE,       \
      ROUGH_DIELECTRIC)                                                                           \
    /* glTF 2.0's material (Appendix B, shared/metallic_roughness.h) */                           \
    X(5u, METALLIC_ROUGHNESS, MetallicRoughness, metallicRoughness, "metallic-roughness",         \
      VKP_FEATURE_BIT(22), VKP_KIND_NON_DELTA | VKP_KIND_MICROFACET | VKP_KIND_LOBE_CHOICE,       \
      METALLIC_ROUGHNESS)

#define VKP_MATERIAL_KIND_COUNT 6u

// Masks over the kinds, as constant expressions: `(0u VKP_MATERIAL_KINDS(F))`
// with F expanding to `| term` per row.
#define VKP_KIND_FEATURE_TERM(id, NAME, Type, key, label, feature, flags, regularized) | (feature)
#define VKP_KIND_NON_DELTA_TERM(id, NAME, Type, key, label, feature, flags, regularized) \
    | (((flags)&VKP_KIND_NON_DELTA) != 0u ? (feature) : VKP_NO_FEATURES)
#define VKP_KIND_MICROFACET_TERM(id, NAME, Type, key, label, feature, flags, regularized) \
    | (((flags)&VKP_KIND_MICROFACET) != 0u ? (feature) : VKP_NO_FEATURES)
#define VKP_KIND_TRANSMITS_TERM(id, NAME, Type, key, label, feature, flags, regularized) \
    | (((flags)&VKP_KIND_TRANSMITS) != 0u ? (feature) : VKP_NO_FEATURES)

#endif  // VKPATH_SHARED_MATERIAL_KINDS_H
