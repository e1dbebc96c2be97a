// The smooth lobes: Lambertian, perfect mirror and smooth dielectric, and
// BsdfSample, what every lobe's sampling returns. Directions are world space
// (or any frame; these lobes take the normal as a parameter) and point away
// from the surface: wo toward the viewer (the previous path vertex), wi
// toward the next vertex (or the light).
//
// Sidedness: diffuse and mirror surfaces are two-sided (they reflect on
// whichever side wo lies, as Scotty3D's do); a dielectric uses the normal to
// tell inside (the side the normal points away from) from outside.
//
// The microfacet lobes (shared/microfacet.h, shared/metallic_roughness.h)
// build on these; shared/bsdf.h dispatches a material to its lobes.
#ifndef VKPATH_SHARED_LOBES_H
#define VKPATH_SHARED_LOBES_H

#include "shared/compat.h"
#include "shared/constants.h"
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
    vec3 direction;    // wi, world space, unit
    vec3 weight;       // f * |cos| / pdf: the factor on the path throughput
    float pdf;         // solid-angle density; for delta lobes the discrete probability
    bool delta;        // a specular lobe: no light sampling, no MIS
    bool valid;        // false: the path ends (e.g. sampled below the surface)
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
VKP_FN vec3 faceForward(vec3 n, vec3 wo) {
    return dot(n, wo) < 0.0f ? -n : n;
}

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

VKP_FN vec3 reflectAbout(vec3 wo, vec3 n) {
    return 2.0f * dot(wo, n) * n - wo;
}

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

// A smooth thin wall (glTF's transmission without a volume): air on both
// sides, so the Fresnel term is the outside's, index ior, from either side,
// and what passes leaves along -wo, tinted, with no change of index
// (etaSquared 1). Reflection is chosen with probability F, as for the solid.
VKP_FN BsdfSample sampleThinDielectric(vec3 reflectance, vec3 transmittance, float ior, vec3 n,
                                       vec3 wo, float u) {
    float cosO = dot(n, wo);
    vec3 nf = cosO > 0.0f ? n : -n;
    float fresnel = fresnelDielectric(abs(cosO), ior);
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
    s.direction = -wo;
    s.weight = transmittance;
    s.pdf = 1.0f - fresnel;
    return s;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_LOBES_H
