// The BSDFs: Lambertian, perfect mirror and smooth dielectric. Directions are
// world space and point away from the surface: wo toward the viewer (the
// previous path vertex), wi toward the next vertex (or the light).
//
// Sidedness: diffuse and mirror surfaces are two-sided (they reflect on
// whichever side wo lies, as Scotty3D's do); a dielectric uses the normal to
// tell inside (the side the normal points away from) from outside.
#ifndef VKPATH_SHARED_BSDF_H
#define VKPATH_SHARED_BSDF_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/material.h"
#include "shared/sampling.h"

VKP_NAMESPACE_BEGIN

// Unpolarised Fresnel reflectance of a smooth dielectric interface for light
// arriving with cosine cosThetaI (> 0: from the outside, < 0: from the inside)
// and relative index eta = n_inside / n_outside. Total internal reflection
// gives 1. (Exact Fresnel equations: Pharr, Jakob, Humphreys, PBR 4th ed.,
// section 9.3.)
VKP_FN float fresnelDielectric(float cosThetaI, float eta) {
    if (eta == 1.0f) return 0.0f;  // no interface (exactly, not 1e-15 from rounding)
    cosThetaI = clamp(cosThetaI, -1.0f, 1.0f);
    if (cosThetaI < 0.0f) {
        eta = 1.0f / eta;
        cosThetaI = -cosThetaI;
    }
    float sin2ThetaI = 1.0f - cosThetaI * cosThetaI;
    float sin2ThetaT = sin2ThetaI / (eta * eta);
    if (sin2ThetaT >= 1.0f) return 1.0f;
    float cosThetaT = sqrt(max(0.0f, 1.0f - sin2ThetaT));
    float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

struct BsdfSample {
    vec3 direction;  // wi, world space, unit
    vec3 weight;     // f * |cos| / pdf: the factor on the path throughput
    float pdf;       // solid-angle density; for delta lobes the discrete probability
    bool delta;      // a specular lobe: no light sampling, no MIS
    bool valid;      // false: the path ends (e.g. sampled below the surface)
    float etaSquared;  // refraction: eta'^2, the factor `weight` divided radiance by; else 1
};

VKP_FN BsdfSample invalidBsdfSample() {
    BsdfSample s;
    s.direction = vec3(0.0f);
    s.weight = vec3(0.0f);
    s.pdf = 0.0f;
    s.delta = false;
    s.valid = false;
    s.etaSquared = 1.0f;
    return s;
}

// ---- Lambertian ---------------------------------------------------------------

// The normal turned to the side of wo (two-sided diffuse and mirror).
VKP_FN vec3 faceForward(vec3 n, vec3 wo) { return dot(n, wo) < 0.0f ? -n : n; }

VKP_FN BsdfSample sampleLambertian(vec3 albedo, vec3 n, vec3 wo, vec2 u) {
    vec3 nf = faceForward(n, wo);
    vec3 local = sampleCosineHemisphere(u);
    BsdfSample s;
    s.direction = normalize(frameToWorld(makeFrame(nf), local));
    s.pdf = cosineHemispherePdf(local.z);
    s.weight = albedo;  // (albedo / pi) * cos / (cos / pi)
    s.delta = false;
    s.valid = s.pdf > 0.0f;
    s.etaSquared = 1.0f;
    return s;
}

// f * |cos(wi)| for a light sample; zero when wi is on the other side from wo.
VKP_FN vec3 evalLambertian(vec3 albedo, vec3 n, vec3 wo, vec3 wi) {
    float cosO = dot(n, wo);
    float cosI = dot(n, wi);
    if (cosO * cosI <= 0.0f) return vec3(0.0f);
    return albedo * (abs(cosI) * VKP_INV_PI);
}

VKP_FN float lambertianPdf(vec3 n, vec3 wo, vec3 wi) {
    float cosO = dot(n, wo);
    float cosI = dot(n, wi);
    if (cosO * cosI <= 0.0f) return 0.0f;
    return abs(cosI) * VKP_INV_PI;
}

// ---- perfect mirror -------------------------------------------------------------

VKP_FN vec3 reflectAbout(vec3 wo, vec3 n) { return 2.0f * dot(wo, n) * n - wo; }

VKP_FN BsdfSample sampleMirror(vec3 reflectance, vec3 n, vec3 wo) {
    BsdfSample s;
    s.direction = normalize(reflectAbout(wo, faceForward(n, wo)));
    s.weight = reflectance;
    s.pdf = 1.0f;
    s.delta = true;
    s.valid = true;
    s.etaSquared = 1.0f;
    return s;
}

// ---- smooth dielectric ----------------------------------------------------------
// Reflection is chosen with probability F and refraction with 1 - F, so the
// weight is the tint alone (F / F); refraction also scales radiance by
// 1 / eta'^2, eta' the relative index across the boundary in the direction
// the light travels toward the viewer (radiance compresses into the denser
// medium; PBR 4th ed., section 9.5.2).
VKP_FN BsdfSample sampleDielectric(vec3 reflectance, vec3 transmittance, float ior, vec3 n, vec3 wo,
                                   float u) {
    float cosO = dot(n, wo);
    bool entering = cosO > 0.0f;  // wo is outside
    float eta = entering ? ior : 1.0f / ior;
    vec3 nf = entering ? n : -n;
    float cosI = abs(cosO);
    float fresnel = fresnelDielectric(cosI, eta);

    BsdfSample s;
    s.delta = true;
    s.valid = true;
    s.etaSquared = 1.0f;
    if (u < fresnel) {
        s.direction = normalize(reflectAbout(wo, nf));
        s.weight = reflectance;
        s.pdf = fresnel;
        return s;
    }
    // Snell's law: wi = -wo / eta + (cosI / eta - cosT) nf.
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    float cosT = sqrt(max(0.0f, 1.0f - sin2T));
    s.direction = normalize(-wo / eta + (cosI / eta - cosT) * nf);
    s.weight = transmittance / (eta * eta);
    s.pdf = 1.0f - fresnel;
    s.etaSquared = eta * eta;
    return s;
}

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
        lifted = tangential * (sqrt(max(0.0f, 1.0f - threshold * threshold)) / sqrt(length2)) + threshold * nf;
    vec3 bent = normalize(wo + lifted);
    return dot(bent, ng) < 0.0f ? -bent : bent;
}

// ---- a material's BSDF: one dispatch over the kinds --------------------------------
// Each kind's test is folded away where the kernel's features exclude it or
// leave it the only one (materialIs, shared/features.h). ng is the geometric
// normal, ns the shading normal (adaptShadingNormal; ns == ng on flat
// surfaces), both world space, unit, oriented alike.

// Samples wi for `material`; u uniform in [0, 1)^2.
VKP_FN BsdfSample sampleBsdf(Material material, vec3 ng, vec3 ns, vec3 wo, vec2 u) {
    BsdfSample s = invalidBsdfSample();
    if (materialIs(material, VKP_MATERIAL_DIFFUSE)) s = sampleLambertian(material.reflectance, ns, wo, u);
    else if (materialIs(material, VKP_MATERIAL_MIRROR)) s = sampleMirror(material.reflectance, ns, wo);
    else if (materialIs(material, VKP_MATERIAL_DIELECTRIC))
        s = sampleDielectric(material.reflectance, material.transmittance, material.ior, ns, wo, u.x);
    if (s.valid && !bsdfSidesAgree(ng, ns, wo, s.direction)) return invalidBsdfSample();
    return s;
}

// f * |cos| of the non-delta lobes (only Lambertian has one).
VKP_FN vec3 evalBsdf(Material material, vec3 ng, vec3 ns, vec3 wo, vec3 wi) {
    if (!materialIs(material, VKP_MATERIAL_DIFFUSE) || !bsdfSidesAgree(ng, ns, wo, wi)) return vec3(0.0f);
    return evalLambertian(material.reflectance, ns, wo, wi);
}

// The solid-angle density with which sampleBsdf picks wi (0 for delta lobes).
VKP_FN float bsdfPdf(Material material, vec3 ng, vec3 ns, vec3 wo, vec3 wi) {
    if (!materialIs(material, VKP_MATERIAL_DIFFUSE) || !bsdfSidesAgree(ng, ns, wo, wi)) return 0.0f;
    return lambertianPdf(ns, wo, wi);
}

// Whether light sampling can reach the material (it has a non-delta lobe).
VKP_FN bool hasNonDeltaLobe(Material material) { return materialIs(material, VKP_MATERIAL_DIFFUSE); }

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_BSDF_H
