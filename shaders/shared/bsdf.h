// A material's BSDF: the rules that join the shading normal to the geometry,
// and the dispatch of a material to its lobes (shared/lobes.h), one switch
// over the kind per function. Directions are world space and point away from
// the surface: wo toward the viewer (the previous path vertex), wi toward the
// next vertex (or the light).
#ifndef VKPATH_SHARED_BSDF_H
#define VKPATH_SHARED_BSDF_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/lobes.h"
#include "shared/material.h"
#include "shared/metallic_roughness.h"
#include "shared/microfacet.h"
#include "shared/microfacet_albedo.h"
#include "shared/precise_math.h"
#include "shared/sampling.h"

VKP_NAMESPACE_BEGIN

// ---- shading normals ----------------------------------------------------------
// A BSDF runs in the frame of the shading normal ns (interpolated vertex
// normals), while the surface the ray meets has the geometric normal ng. Two
// rules keep the two consistent:
//
// - Sidedness follows the geometry (Veach's thesis, section 5.3; PBR 3rd ed.,
//   section 9.1): whether wi is a reflection or a transmission is decided
//   by ng, as the surface really is, and a direction the shading frame
//   classifies otherwise carries nothing (bsdfSidesAgree). No light leaks
//   through a surface and none is taken from behind it.
// - No black facets: where wo lies below ns's hemisphere, or a mirror
//   reflection about ns would go into the surface, ns is bent just enough that
//   the reflection of wo about it stays above the geometric surface (the
//   normal adaptation of Keller et al., "The Iray Light Transport Simulation
//   and Rendering System", 2017, appendix A; the same rule Blender's Cycles
//   applies). The lifted reflection is kept min(0.9 cos_g, 0.01) above the
//   surface, cos_g the cosine of wo with the geometric normal.
//
// With ns == ng both are exact no-ops, so flat triangles shade bit for bit as
// with the geometric normal alone.

// Whether the shading frame and the geometry agree on wi being a reflection
// of wo (same side) or a transmission (other side).
VKP_FN bool bsdfSidesAgree(vec3 ng, vec3 ns, vec3 wo, vec3 wi) {
    if (!hasFeature(VKP_FEATURE_SHADING_NORMALS)) return true;  // then ns == ng
    return (dot(ng, wo) * dot(ng, wi) > 0.0f) == (dot(ns, wo) * dot(ns, wi) > 0.0f);
}

// ns adapted to wo as described above, oriented like ng (the outward side of
// a dielectric stays the geometry's).
VKP_FN vec3 adaptShadingNormal(vec3 ng, vec3 ns, vec3 wo) {
    vec3 nf = faceForward(ng, wo);
    vec3 sf = dot(ns, nf) < 0.0f ? -ns : ns;
    float threshold = min(0.9f * dot(wo, nf), 0.01f);
    vec3 r = reflectAbout(wo, sf);
    float height = dot(r, nf);
    if (!(height < threshold)) return dot(sf, ng) < 0.0f ? -sf : sf;
    vec3 tangential = r - height * nf;
    float length2 = dot(tangential, tangential);
    vec3 lifted = nf;
    if (length2 > 0.0f)
        lifted = tangential * (sqrt(max(0.0f, 1.0f - threshold * threshold)) / sqrt(length2)) +
                 threshold * nf;
    vec3 bent = normalize(wo + lifted);
    return dot(bent, ng) < 0.0f ? -bent : bent;
}

// A sample drawn in `frame` as a world-space one.
VKP_FN BsdfSample sampleToWorld(Frame frame, BsdfSample s) {
    if (s.valid) s.direction = normalize(frameToWorld(frame, s.direction));
    return s;
}

// ---- path regularisation ----------------------------------------------------------------
// Kaplanyan and Dachsbacher 2013, "Path Space Regularization for Holistic and
// Robust Light Transport": after a path's first non-delta scattering, delta
// and near-delta lobes are widened, so that light reached only through them
// (caustics seen via a diffuse surface) is found by light sampling and
// nearby BSDF samples instead of by rare hits. Biased (the image blurs what
// those lobes show), consistent as the alpha goes to 0. The rule is pbrt-v4's
// (BSDF::Regularize with its TrowbridgeReitzDistribution::Regularize) with
// the floor a knob: every lobe of GGX alpha below `alpha` gets `alpha`; the
// mirror becomes the conductor of the same constant reflectance, the smooth
// glass the rough dielectric of the same index and tints (each kind's
// regularizeTypeMaterial below, into the kind its registry row names).

// A microfacet kind's lobe roughened to at least `roughness`.
VKP_FN Material regularizeMicrofacetMaterial(Material material, float roughness) {
    material.roughness = max(material.roughness, roughness);
    return material;
}

// ---- the kinds' function sets -------------------------------------------------------------
// Each row of the registry (shared/material_kinds.h) has five functions here,
// named after its Type, which the dispatch below calls:
//
//   BsdfSample sampleTypeMaterial(material, ns, wo, u, uc)  wi drawn from its lobes
//   vec3 evalTypeMaterial(material, ns, wo, wi)             f |cos| of its non-delta lobes
//   float pdfTypeMaterial(material, ns, wo, wi)             sampleTypeMaterial's solid-angle
//                                                           density of wi (0 for delta lobes)
//   bool nonDeltaTypeMaterial(material)                     whether it has a non-delta lobe
//   Material regularizeTypeMaterial(material, roughness)    widened by path regularisation
//   vec3 albedoTypeMaterial(material)                       the albedo AOV, in [0, 1]
//                                                           (materialAlbedo below)
//
// ns is the shading normal (world space, unit, oriented like the geometric
// normal), wo and wi point away from the surface; u is uniform in [0, 1)^2,
// uc in [0, 1) (read only by kinds flagged VKP_KIND_LOBE_CHOICE; smooth glass
// chooses its lobe with u.x). The microfacet kinds work in the local frame of
// ns (microfacet.h, metallic_roughness.h).

// Diffuse: Lambertian (lobes.h).
VKP_FN BsdfSample sampleDiffuseMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec2 u,
                                        float /*uc*/) {
    return sampleLambertian(material.reflectance, ns, wo, u);
}
VKP_FN vec3 evalDiffuseMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    return evalLambertian(material.reflectance, ns, wo, wi);
}
VKP_FN float pdfDiffuseMaterial(VKP_IN(Material) /*material*/, vec3 ns, vec3 wo, vec3 wi) {
    return lambertianPdf(ns, wo, wi);
}
VKP_FN bool nonDeltaDiffuseMaterial(VKP_IN(Material) /*material*/) {
    return true;
}
VKP_FN Material regularizeDiffuseMaterial(Material material, float /*roughness*/) {
    return material;
}
VKP_FN vec3 albedoDiffuseMaterial(VKP_IN(Material) material) {
    return material.reflectance;
}

// Mirror: one delta lobe (lobes.h).
VKP_FN BsdfSample sampleMirrorMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec2 /*u*/,
                                       float /*uc*/) {
    return sampleMirror(material.reflectance, ns, wo);
}
VKP_FN vec3 evalMirrorMaterial(VKP_IN(Material), vec3, vec3, vec3) {
    return vec3(0.0f);
}
VKP_FN float pdfMirrorMaterial(VKP_IN(Material), vec3, vec3, vec3) {
    return 0.0f;
}
VKP_FN bool nonDeltaMirrorMaterial(VKP_IN(Material)) {
    return false;
}
// The conductor of the same constant reflectance.
VKP_FN Material regularizeMirrorMaterial(Material material, float roughness) {
    material.kind = VKP_MATERIAL_CONDUCTOR;
    material.flags = VKP_MATERIAL_CONSTANT_FRESNEL;
    material.roughness = roughness;
    return material;
}
// The reflected albedo (seen only where a path ends on the mirror: the AOV
// follows a delta bounce to the next hit).
VKP_FN vec3 albedoMirrorMaterial(VKP_IN(Material) material) {
    return material.reflectance;
}

// Smooth glass: delta reflection and refraction (lobes.h).
VKP_FN BsdfSample sampleDielectricMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec2 u,
                                           float /*uc*/) {
    if (materialThinWalled(material))
        return sampleThinDielectric(material.reflectance, material.transmittance, material.ior, ns,
                                    wo, u.x);
    return sampleDielectric(material.reflectance, material.transmittance, material.ior, ns, wo,
                            u.x);
}
VKP_FN vec3 evalDielectricMaterial(VKP_IN(Material), vec3, vec3, vec3) {
    return vec3(0.0f);
}
VKP_FN float pdfDielectricMaterial(VKP_IN(Material), vec3, vec3, vec3) {
    return 0.0f;
}
VKP_FN bool nonDeltaDielectricMaterial(VKP_IN(Material)) {
    return false;
}
// The rough dielectric of the same index and tints.
VKP_FN Material regularizeDielectricMaterial(Material material, float roughness) {
    material.kind = VKP_MATERIAL_ROUGH_DIELECTRIC;
    material.roughness = roughness;
    return material;
}
// OIDN's 1 for a dielectric (seen only where a path ends on the glass: the
// AOV follows a delta bounce to the next hit, which over a pixel's samples
// makes the Fresnel blend of the reflected and transmitted albedos).
VKP_FN vec3 albedoDielectricMaterial(VKP_IN(Material)) {
    return vec3(1.0f);
}

// Whether `material`'s GGX lobe is rougher along Material::anisotropyDirection
// than across it (KHR_materials_anisotropy).
VKP_FN bool materialAnisotropic(VKP_IN(Material) material) {
    return hasFeature(VKP_FEATURE_ANISOTROPY) && material.anisotropy > 0.0f;
}

// The GGX alphas of a microfacet kind along the local frame's s and t
// (materialFrame): alpha = roughness^2 (glTF 2.0 Appendix B, and the Disney
// convention) both ways; anisotropic, KHR_materials_anisotropy's
// alpha_t = mix(alpha, 1, strength^2) along the direction and alpha_b =
// alpha across it, each at least VKP_MICROFACET_SMOOTH_ALPHA (the extension
// clamps alpha_b to 0.001): an anisotropic lobe is never a delta.
VKP_FN vec2 materialAlpha(VKP_IN(Material) material) {
    float alpha = material.roughness * material.roughness;
    if (!materialAnisotropic(material)) return vec2(alpha);
    float along = alpha + (1.0f - alpha) * (material.anisotropy * material.anisotropy);
    return max(vec2(along, alpha), vec2(VKP_MICROFACET_SMOOTH_ALPHA));
}

// The local frame of a microfacet kind at shading normal ns: any frame
// (makeFrame) for an isotropic lobe; for an anisotropic one, s along
// Material::anisotropyDirection made orthogonal to ns, the direction of
// materialAlpha's first alpha.
VKP_FN Frame materialFrame(VKP_IN(Material) material, vec3 ns) {
    if (!materialAnisotropic(material)) return makeFrame(ns);
    vec3 s = material.anisotropyDirection - dot(material.anisotropyDirection, ns) * ns;
    float length2 = dot(s, s);
    if (!(length2 > 1e-12f)) return makeFrame(ns);
    Frame f;
    f.s = s / sqrt(length2);
    f.t = exactCross(ns, f.s);
    f.n = ns;
    return f;
}

VKP_FN Conductor materialConductor(VKP_IN(Material) material) {
    Conductor c;
    c.alpha = materialAlpha(material);
    c.fresnel = (material.flags & VKP_MATERIAL_COMPLEX_FRESNEL) != 0u    ? VKP_FRESNEL_COMPLEX
                : (material.flags & VKP_MATERIAL_CONSTANT_FRESNEL) != 0u ? VKP_FRESNEL_CONSTANT
                                                                         : VKP_FRESNEL_SCHLICK;
    c.f0 = material.reflectance;
    c.eta = material.reflectance;
    c.k = material.transmittance;
    c.multipleScattering = material.multipleScattering;
    return c;
}
VKP_FN BsdfSample sampleConductorMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec2 u,
                                          float /*uc*/) {
    Frame frame = materialFrame(material, ns);
    return sampleToWorld(frame,
                         sampleConductor(materialConductor(material), frameToLocal(frame, wo), u));
}
VKP_FN vec3 evalConductorMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    Frame frame = materialFrame(material, ns);
    return evalConductor(materialConductor(material), frameToLocal(frame, wo),
                         frameToLocal(frame, wi));
}
VKP_FN float pdfConductorMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    Frame frame = materialFrame(material, ns);
    return conductorPdf(materialConductor(material), frameToLocal(frame, wo),
                        frameToLocal(frame, wi));
}
// A delta below VKP_MICROFACET_SMOOTH_ALPHA.
VKP_FN bool nonDeltaConductorMaterial(VKP_IN(Material) material) {
    return !microfacetIsSmooth(materialAlpha(material));
}
VKP_FN Material regularizeConductorMaterial(Material material, float roughness) {
    return regularizeMicrofacetMaterial(material, roughness);
}
// The reflectivity at normal incidence (OIDN's first choice for metals):
// Schlick's F0, or the exact Fresnel of the complex index at cos 1.
VKP_FN vec3 albedoConductorMaterial(VKP_IN(Material) material) {
    if ((material.flags & VKP_MATERIAL_COMPLEX_FRESNEL) == 0u) return material.reflectance;
    return vec3(fresnelComplex(1.0f, material.reflectance.x, material.transmittance.x),
                fresnelComplex(1.0f, material.reflectance.y, material.transmittance.y),
                fresnelComplex(1.0f, material.reflectance.z, material.transmittance.z));
}

// Rough glass (microfacet.h).
VKP_FN RoughDielectric materialRoughDielectric(VKP_IN(Material) material) {
    RoughDielectric d;
    d.alpha = materialAlpha(material);
    d.ior = material.ior;
    d.reflectance = material.reflectance;
    d.transmittance = material.transmittance;
    d.multipleScattering = material.multipleScattering;
    d.thin = materialThinWalled(material);
    return d;
}
VKP_FN BsdfSample sampleRoughDielectricMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec2 u,
                                                float uc) {
    Frame frame = materialFrame(material, ns);
    return sampleToWorld(frame, sampleRoughDielectric(materialRoughDielectric(material),
                                                      frameToLocal(frame, wo), u, uc));
}
VKP_FN vec3 evalRoughDielectricMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    Frame frame = materialFrame(material, ns);
    return evalRoughDielectric(materialRoughDielectric(material), frameToLocal(frame, wo),
                               frameToLocal(frame, wi));
}
VKP_FN float pdfRoughDielectricMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    Frame frame = materialFrame(material, ns);
    return roughDielectricPdf(materialRoughDielectric(material), frameToLocal(frame, wo),
                              frameToLocal(frame, wi));
}
// A delta below VKP_MICROFACET_SMOOTH_ALPHA, and no lobe at all at index 1.
VKP_FN bool nonDeltaRoughDielectricMaterial(VKP_IN(Material) material) {
    return !microfacetIsSmooth(materialAlpha(material)) && material.ior != 1.0f;
}
VKP_FN Material regularizeRoughDielectricMaterial(Material material, float roughness) {
    return regularizeMicrofacetMaterial(material, roughness);
}
// OIDN's 1 for a dielectric that is not a delta.
VKP_FN vec3 albedoRoughDielectricMaterial(VKP_IN(Material)) {
    return vec3(1.0f);
}

// glTF's metallic-roughness material (metallic_roughness.h).
VKP_FN MetallicRoughness materialMetallicRoughness(VKP_IN(Material) material) {
    MetallicRoughness p;
    p.baseColor = material.reflectance;
    p.metallic = material.metallic;
    p.alpha = materialAlpha(material);
    p.specularF0 = material.transmittance;
    p.specularF90 = material.specular;
    p.multipleScattering = material.multipleScattering;
    p.sheenColor = material.sheenColor;
    p.sheenAlpha = sheenAlpha(material.sheenRoughness);
    p.sheenLobeAlbedo = material.sheenLobeAlbedo;
    p.clearcoat = material.clearcoat;
    p.coatAlpha = vec2(material.clearcoatRoughness * material.clearcoatRoughness);
    p.coatNormal = vec3(0.0f, 0.0f, 1.0f);
    p.diffuseTransmission = material.diffuseTransmission;
    p.diffuseTransmissionColor = material.diffuseTransmissionColor;
    p.iridescence = material.iridescence;
    p.iridescenceIor = material.iridescenceIor;
    p.iridescenceThickness = material.iridescenceThickness;
    return p;
}
// ... in `frame`, with the coat's own normal (Material::clearcoatNormal) there.
VKP_FN MetallicRoughness materialMetallicRoughness(VKP_IN(Material) material, Frame frame) {
    MetallicRoughness p = materialMetallicRoughness(material);
    if (hasFeature(VKP_FEATURE_CLEARCOAT) && material.clearcoatNormal != vec3(0.0f))
        p.coatNormal = normalize(frameToLocal(frame, material.clearcoatNormal));
    return p;
}
VKP_FN BsdfSample sampleMetallicRoughnessMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo,
                                                  vec2 u, float uc) {
    Frame frame = materialFrame(material, ns);
    return sampleToWorld(frame, sampleMetallicRoughness(materialMetallicRoughness(material, frame),
                                                        frameToLocal(frame, wo), u, uc));
}
VKP_FN vec3 evalMetallicRoughnessMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    Frame frame = materialFrame(material, ns);
    return evalMetallicRoughness(materialMetallicRoughness(material, frame),
                                 frameToLocal(frame, wo), frameToLocal(frame, wi));
}
VKP_FN float pdfMetallicRoughnessMaterial(VKP_IN(Material) material, vec3 ns, vec3 wo, vec3 wi) {
    Frame frame = materialFrame(material, ns);
    return metallicRoughnessPdf(materialMetallicRoughness(material, frame), frameToLocal(frame, wo),
                                frameToLocal(frame, wi));
}
// Its diffuse lobe stays unless it is wholly metal; a sheen or a rough coat
// over it has none.
VKP_FN bool nonDeltaMetallicRoughnessMaterial(VKP_IN(Material) material) {
    return !microfacetIsSmooth(materialAlpha(material)) || material.metallic < 1.0f ||
           (hasFeature(VKP_FEATURE_SHEEN) && material.sheenColor != vec3(0.0f)) ||
           (hasFeature(VKP_FEATURE_CLEARCOAT) && material.clearcoat > 0.0f &&
            !microfacetIsSmooth(vec2(material.clearcoatRoughness * material.clearcoatRoughness)));
}
// Both GGX lobes roughened, the base's and the coat's.
VKP_FN Material regularizeMetallicRoughnessMaterial(Material material, float roughness) {
    if (hasFeature(VKP_FEATURE_CLEARCOAT))
        material.clearcoatRoughness = max(material.clearcoatRoughness, roughness);
    return regularizeMicrofacetMaterial(material, roughness);
}
// The base colour: glTF's metal reflects it at normal incidence (OIDN's
// choice for metals) and its dielectric's diffuse lobe has it as albedo, so
// the mix of the two by `metallic` is the base colour itself; the dielectric
// layer's specular reflection is left out, as OIDN allows for a clear coat
// that does not absorb.
VKP_FN vec3 albedoMetallicRoughnessMaterial(VKP_IN(Material) material) {
    return material.reflectance;
}

// ---- a material's BSDF: one dispatch over the kinds --------------------------------
// Each function is one switch over the kind, its cases made from the
// registry (materialKind folds the switch to one case where the kernel meets
// one kind); each case is guarded by its feature bit (materialMayBe), so a
// kernel compiles only the kinds its scene has (shared/features.h). ng is the
// geometric normal, ns the shading normal (adaptShadingNormal; ns == ng on
// flat surfaces), both world space, unit, oriented alike.

// Samples wi for `material`; u uniform in [0, 1)^2 picks the direction, uc
// uniform in [0, 1) the lobe where a kind chooses between lobes with a number
// of its own (VKP_KIND_LOBE_CHOICE).
VKP_FN BsdfSample sampleBsdf(VKP_IN(Material) material, vec3 ng, vec3 ns, vec3 wo, vec2 u,
                             float uc) {
    BsdfSample s = invalidBsdfSample();
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized)      \
    case id:                                                                        \
        if (materialMayBe(id)) s = sample##Type##Material(material, ns, wo, u, uc); \
        break;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            break;
    }
    if (s.valid && !bsdfSidesAgree(ng, ns, wo, s.direction)) return invalidBsdfSample();
    return s;
}

// Whether sampleBsdf reads uc for `material` (so the caller draws it only then).
VKP_FN bool bsdfNeedsLobeChoice(VKP_IN(Material) material) {
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized) \
    case id:                                                                   \
        return ((flags)&VKP_KIND_LOBE_CHOICE) != 0u && materialMayBe(id);
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            return false;
    }
}

// f * |cos| of the non-delta lobes.
VKP_FN vec3 evalBsdf(VKP_IN(Material) material, vec3 ng, vec3 ns, vec3 wo, vec3 wi) {
    if (!bsdfSidesAgree(ng, ns, wo, wi)) return vec3(0.0f);
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized)    \
    case id:                                                                      \
        if (materialMayBe(id)) return eval##Type##Material(material, ns, wo, wi); \
        break;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            break;
    }
    return vec3(0.0f);
}

// The solid-angle density with which sampleBsdf picks wi (0 for delta lobes).
VKP_FN float bsdfPdf(VKP_IN(Material) material, vec3 ng, vec3 ns, vec3 wo, vec3 wi) {
    if (!bsdfSidesAgree(ng, ns, wo, wi)) return 0.0f;
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized)   \
    case id:                                                                     \
        if (materialMayBe(id)) return pdf##Type##Material(material, ns, wo, wi); \
        break;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            break;
    }
    return 0.0f;
}

// Whether light sampling can reach the material (it has a non-delta lobe);
// host/wavefront/kernel_features.cpp shadowRaysPerVertex says the same per
// feature (VKP_FEATURES_NON_DELTA).
VKP_FN bool hasNonDeltaLobe(VKP_IN(Material) material) {
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized) \
    case id:                                                                   \
        return ((flags)&VKP_KIND_NON_DELTA) != 0u && materialMayBe(id) &&      \
               nonDelta##Type##Material(material);
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            return false;
    }
}

// The albedo AOV of `material` (--aov albedo, the denoiser's guide): "the
// approximate color of the surfaces independent of illumination and viewing
// angle", in [0, 1], as Intel Open Image Denoise's documentation defines it
// (doc/api.md, section "RT", subsection "Albedos"; each kind's choice at its
// albedoTypeMaterial above).
VKP_FN vec3 materialAlbedo(VKP_IN(Material) material) {
    vec3 albedo = vec3(0.0f);
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized) \
    case id:                                                                   \
        if (materialMayBe(id)) albedo = albedo##Type##Material(material);      \
        break;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            break;
    }
    return clamp(albedo, vec3(0.0f), vec3(1.0f));
}

// `material` widened by path regularisation to GGX alpha `alpha` (see above);
// alpha 0 leaves it as it is.
VKP_FN Material regularizedMaterial(Material material, float alpha) {
    if (!(alpha > 0.0f)) return material;
    float roughness = sqrt(alpha);
    switch (materialKind(material)) {
#define VKP_KIND_CASE(id, NAME, Type, key, label, feature, flags, regularized)         \
    case id:                                                                           \
        if (materialMayBe(id)) return regularize##Type##Material(material, roughness); \
        break;
        VKP_MATERIAL_KINDS(VKP_KIND_CASE)
#undef VKP_KIND_CASE
        default:
            break;
    }
    return material;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_BSDF_H
