// glTF 2.0's metallic-roughness material (the specification's Appendix B,
// "BRDF Implementation"), with KHR_materials_specular's weight and colour:
//
//   material        = mix(dielectric_brdf, metal_brdf, metallic)
//   metal_brdf      = specular_brdf(alpha) * (base + (1 - base) (1 - |V.H|)^5)
//   dielectric_brdf = (1 - max(F_d)) diffuse_brdf(base) + F_d specular_brdf(alpha)
//   F_d             = f0 + (f90 - f0) (1 - |V.H|)^5
//
// with specular_brdf = D G2 / (4 |N.L| |N.V|) the GGX lobe of microfacet.h
// without Fresnel, H the half vector of V = wo and L = wi, and the
// dielectric layer's f0 = min(((ior - 1) / (ior + 1))^2 specularColor, 1) x
// specular and f90 = specular (KHR_materials_specular's fresnel_mix with its
// weight folded into both: weight x Schlick(f0, 1) = Schlick(weight f0,
// weight); the core material is specular = 1, specularColor = 1, ior 1.5).
// The host computes f0 and f90 (host/wavefront/gpu_scene.cpp).
//
// Sampling picks one of two lobes per sample, GGX visible normals reflected
// (microfacet.h) or the cosine-weighted hemisphere, with a probability
// estimated from each lobe's weight at wo (specularProbability); the pdf of
// the sample is the exact mixture of both lobes' densities and its weight is
// the whole f |cos| divided by it, so the choice affects only the variance
// (the one-sample model of Veach's thesis, section 9.2.4). Below
// VKP_MICROFACET_SMOOTH_ALPHA the specular lobe is a delta (the mirror
// weighted by the Fresnel terms at wo.n): chosen with probability p, weight
// F / p, pdf p, delta; eval and pdf are then the diffuse lobe's alone.
//
// Two-sided like the Lambertian and the conductor: a wo below the surface
// sees the same material (the frame flipped). Directions in the local frame
// (normal +z), as in microfacet.h.
#ifndef VKPATH_SHARED_METALLIC_ROUGHNESS_H
#define VKPATH_SHARED_METALLIC_ROUGHNESS_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/lobes.h"
#include "shared/microfacet.h"
#include "shared/sampling.h"

VKP_NAMESPACE_BEGIN

struct MetallicRoughness {
    vec3 baseColor;     // diffuse albedo of the dielectric, F0 of the metal
    float metallic;     // 0: dielectric, 1: metal, between: the mix
    vec2 alpha;         // GGX roughness (alpha = roughness^2)
    vec3 specularF0;    // the dielectric layer's Fresnel at normal incidence, weight included
    float specularF90;  // ... and at grazing incidence (the layer's weight)
    // (1 - E(mu_o)) / E(mu_o) for this wo, E the white GGX lobe's albedo: the
    // specular lobe is scaled by 1 + F(1) x this, F its Fresnel factor
    // (multiple-scattering compensation, shared/microfacet_albedo.h, as the
    // conductor); 0: single scattering
    float multipleScattering;
};

VKP_FN float largestComponent(vec3 v) {
    return max(max(v.x, v.y), v.z);
}
VKP_FN float meanComponent(vec3 v) {
    return (v.x + v.y + v.z) * (1.0f / 3.0f);
}

// F_d above, at cosine c = |wo.h|.
VKP_FN vec3 dielectricLayerFresnel(MetallicRoughness p, float c) {
    float x = 1.0f - clamp(c, 0.0f, 1.0f);
    float x2 = x * x;
    return p.specularF0 + (vec3(p.specularF90) - p.specularF0) * (x2 * x2 * x);
}

// The Fresnel factor of the specular lobe as a whole: (1 - metallic) F_d +
// metallic x Schlick(base colour).
VKP_FN vec3 metallicRoughnessSpecularFresnel(MetallicRoughness p, float c) {
    return mix(dielectricLayerFresnel(p, c), fresnelSchlick(p.baseColor, c), p.metallic);
}

// The probability of sampling the specular lobe at wo (o.z = cos theta_o):
// each lobe's weight estimated with the Fresnel terms at the macro normal
// (h = n), in proportion. A lobe that cannot reflect anything (a metal's
// diffuse lobe, the layer of a black non-metal with specular 0) gets none; one
// that can gets at least 5%, since the estimate at h = n may be 0 where the
// Fresnel terms at other half vectors are not (a black metal at normal
// incidence): the floor keeps every direction where f > 0 sampled, at a cost
// of at most 5% of the samples.
VKP_FN float specularProbability(MetallicRoughness p, float cosO) {
    bool specular = p.metallic > 0.0f || p.specularF90 > 0.0f;
    bool diffuse = p.metallic < 1.0f && largestComponent(p.baseColor) > 0.0f &&
                   (largestComponent(p.specularF0) < 1.0f || p.specularF90 < 1.0f);
    if (!diffuse) return specular ? 1.0f : 0.0f;
    if (!specular) return 0.0f;
    vec3 fd = dielectricLayerFresnel(p, cosO);
    float es = meanComponent(mix(fd, fresnelSchlick(p.baseColor, cosO), p.metallic));
    float ed = (1.0f - p.metallic) * (1.0f - largestComponent(fd)) * meanComponent(p.baseColor);
    if (!(es + ed > 0.0f)) return 0.5f;
    return clamp(es / (es + ed), 0.05f, 0.95f);
}

// f |cos wi| for o, i in the upper hemisphere; the diffuse lobe alone when the
// specular one is a delta.
VKP_FN vec3 evalMetallicRoughnessUpper(MetallicRoughness p, vec3 o, vec3 i) {
    vec3 h = normalize(o + i);
    float c = dot(o, h);
    vec3 fd = dielectricLayerFresnel(p, c);
    vec3 f =
        ((1.0f - p.metallic) * (1.0f - largestComponent(fd)) * (i.z * VKP_INV_PI)) * p.baseColor;
    if (microfacetIsSmooth(p.alpha)) return f;
    // D G2 / (4 zo zi) x zi = D zi / (2 (zi Lo + zo Li)), as evalConductor.
    float d = i.z * ggxStretchedLength(o, p.alpha) + o.z * ggxStretchedLength(i, p.alpha);
    float specular = ggxD(h, p.alpha) * i.z / (2.0f * d);
    vec3 fresnel = metallicRoughnessSpecularFresnel(p, c);
    if (p.multipleScattering > 0.0f)
        fresnel *= vec3(1.0f) + metallicRoughnessSpecularFresnel(p, 1.0f) * p.multipleScattering;
    return f + fresnel * specular;
}

// The mixture's density of i for o (upper hemisphere, pSpec from specularProbability).
VKP_FN float metallicRoughnessPdfUpper(MetallicRoughness p, vec3 o, vec3 i, float pSpec) {
    float pdf = (1.0f - pSpec) * cosineHemispherePdf(i.z);
    if (microfacetIsSmooth(p.alpha)) return pdf;
    vec3 h = normalize(o + i);
    // D_wo(h) / (4 wo.h) = D / (2 (zo + Lo)), the conductor's reflection density.
    return pdf + pSpec * ggxD(h, p.alpha) / (2.0f * (o.z + ggxStretchedLength(o, p.alpha)));
}

// u picks the direction within the lobe, uc the lobe.
VKP_FN BsdfSample sampleMetallicRoughness(MetallicRoughness p, vec3 wo, vec2 u, float uc) {
    if (wo.z == 0.0f) return invalidBsdfSample();
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    float pSpec = specularProbability(p, o.z);
    vec3 i;
    if (uc < pSpec) {
        if (microfacetIsSmooth(p.alpha)) {
            BsdfSample s;
            s.direction = side * vec3(-o.x, -o.y, o.z);
            s.weight = metallicRoughnessSpecularFresnel(p, o.z) / pSpec;
            s.pdf = pSpec;
            s.delta = true;
            s.valid = true;
            s.etaSquared = 1.0f;
            return s;
        }
        vec3 m = sampleGgxVisibleNormal(o, p.alpha, u);
        float om = dot(o, m);
        if (om <= 0.0f) return invalidBsdfSample();
        i = 2.0f * om * m - o;
    } else {
        i = sampleCosineHemisphere(u);
    }
    // Reflected below the macro surface: lost, as the conductor's.
    if (i.z <= 0.0f) return invalidBsdfSample();
    float pdf = metallicRoughnessPdfUpper(p, o, i, pSpec);
    if (!(pdf > 0.0f)) return invalidBsdfSample();
    BsdfSample s;
    s.direction = side * i;
    s.pdf = pdf;
    s.weight = evalMetallicRoughnessUpper(p, o, i) / pdf;
    s.delta = false;
    s.valid = true;
    s.etaSquared = 1.0f;
    return s;
}

VKP_FN vec3 evalMetallicRoughness(MetallicRoughness p, vec3 wo, vec3 wi) {
    if (wo.z * wi.z <= 0.0f) return vec3(0.0f);
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    return evalMetallicRoughnessUpper(p, side * wo, side * wi);
}

VKP_FN float metallicRoughnessPdf(MetallicRoughness p, vec3 wo, vec3 wi) {
    if (wo.z * wi.z <= 0.0f) return 0.0f;
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    return metallicRoughnessPdfUpper(p, o, side * wi, specularProbability(p, o.z));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_METALLIC_ROUGHNESS_H
