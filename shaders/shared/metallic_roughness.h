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
// A thin film may lie on it (KHR_materials_iridescence, shared/thin_film.h):
// both Fresnel terms, the metal's and the dielectric layer's, become
// mix(F, F_film, iridescence), F_film the film's reflectance over the same
// base (its F0; the dielectric's without the specular weight, which then
// multiplies it), in air (a clear coat above does not change the film's
// outside index here).
//
// Its diffuse lobe may pass light to the back (KHR_materials_diffuse_
// transmission): diffuse_brdf(base) becomes mix(diffuse_brdf(base),
// diffuse_btdf(diffuseTransmissionColor), diffuseTransmission), the btdf the
// Lambertian lobe below the surface, weighted by the dielectric layer's
// 1 - max(F_d) at the half vector of wo and wi's mirror image above the
// surface (the extension's thin-walled reading: the light leaves from the
// other side of the same point). The cosine sample of the diffuse lobe is
// mirrored below with a probability from the two colours
// (diffuseTransmissionProbability).
//
// Two layers may lie over it (the layered material below): a sheen
// (KHR_materials_sheen, shared/sheen.h) and over that a clear coat
// (KHR_materials_clearcoat), as the extensions stack them:
//
//   layered    = mix(sheened, coat_brdf, clearcoat F_c(|n.v|))
//   sheened    = sheenColor f_sheen / max(1, E) + (1 - max(sheenColor) min(1, E)) material
//   coat_brdf  = specular_brdf(clearcoatRoughness^2), the GGX lobe without Fresnel
//   F_c(c)     = 0.04 + 0.96 (1 - c)^5, the coat's index 1.5
//
// E = E_sheen(|n.v|) is the white sheen lobe's directional albedo (a table,
// shared/microfacet_albedo.h); the extension's notes allow this form of the
// albedo scaling, which reads E at wo only, beside one that also reads it at
// wi. vkpath takes it because it conserves energy exactly: a white sheen over
// a base of albedo 1 returns 1 at every angle, and E is read once per hit
// (Material::sheenLobeAlbedo). Like the compensation it makes f depend on wo
// apart from wi (not reciprocal). With Estevez and Kulla's shadowing fit the
// lobe's albedo exceeds 1 at grazing angles below sheen roughness ~0.3 (up to
// 6.1 as the roughness goes to 0: the table, tests/kernels/
// albedo_table_test.cpp): there the lobe is scaled down to albedo 1 (the
// division by max(1, E)) and takes all the light from the base. (Khronos'
// sample viewer clamps the visibility term to 1 instead.) The coat is
// uncompensated and uses the shading normal, as the base does, unless it has
// a normal map of its own (clearcoatNormalTexture): then its lobe, F_c and
// cosine are taken about that normal (MetallicRoughness::coatNormal, toCoat).
//
// Two-sided like the Lambertian and the conductor: a wo below the surface
// sees the same material (the frame flipped). Directions in the local frame
// (normal +z), as in microfacet.h.
#ifndef VKPATH_SHARED_METALLIC_ROUGHNESS_H
#define VKPATH_SHARED_METALLIC_ROUGHNESS_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/features.h"
#include "shared/lobes.h"
#include "shared/microfacet.h"
#include "shared/sampling.h"
#include "shared/sheen.h"
#include "shared/thin_film.h"

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
    // The layers (0: none): the sheen's colour, alpha and white lobe's albedo
    // at this wo (E_sheen(mu_o)), the coat's weight and GGX alpha.
    vec3 sheenColor;
    float sheenAlpha;
    float sheenLobeAlbedo;
    float clearcoat;
    vec2 coatAlpha;
    // The coat's normal in this frame: (0, 0, 1), the shading normal, unless
    // the coat has a normal map of its own (facing wo)
    vec3 coatNormal;
    // The diffuse lobe's share that passes to the back and its colour (0: none)
    float diffuseTransmission;
    vec3 diffuseTransmissionColor;
    // The thin film's weight (0: none), index and thickness (nm)
    float iridescence;
    float iridescenceIor;
    float iridescenceThickness;
};

VKP_FN bool hasIridescence(MetallicRoughness p) {
    return hasFeature(VKP_FEATURE_IRIDESCENCE) && p.iridescence > 0.0f;
}

VKP_FN bool hasDiffuseTransmission(MetallicRoughness p) {
    return hasFeature(VKP_FEATURE_DIFFUSE_TRANSMISSION) && p.diffuseTransmission > 0.0f;
}

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
    vec3 fd = p.specularF0 + (vec3(p.specularF90) - p.specularF0) * (x2 * x2 * x);
    if (!hasIridescence(p) || !(p.specularF90 > 0.0f)) return fd;
    vec3 film = p.specularF90 * thinFilmFresnel(1.0f, p.iridescenceIor, p.iridescenceThickness,
                                                1.0f - x, p.specularF0 / p.specularF90);
    return mix(fd, film, p.iridescence);
}

// The metal's Fresnel term: Schlick's with F0 the base colour, under the film.
VKP_FN vec3 metalFresnel(MetallicRoughness p, float c) {
    vec3 f = fresnelSchlick(p.baseColor, c);
    if (!hasIridescence(p)) return f;
    return mix(f,
               thinFilmFresnel(1.0f, p.iridescenceIor, p.iridescenceThickness, clamp(c, 0.0f, 1.0f),
                               p.baseColor),
               p.iridescence);
}

// The Fresnel factor of the specular lobe as a whole: (1 - metallic) F_d +
// metallic x Schlick(base colour).
VKP_FN vec3 metallicRoughnessSpecularFresnel(MetallicRoughness p, float c) {
    return mix(dielectricLayerFresnel(p, c), metalFresnel(p, c), p.metallic);
}

// The diffuse lobe's albedo before the Fresnel weight: its reflection's and,
// with diffuse transmission, its transmission's, as mean components.
VKP_FN vec2 diffuseAlbedos(MetallicRoughness p) {
    if (!hasDiffuseTransmission(p)) return vec2(meanComponent(p.baseColor), 0.0f);
    return vec2((1.0f - p.diffuseTransmission) * meanComponent(p.baseColor),
                p.diffuseTransmission * meanComponent(p.diffuseTransmissionColor));
}

// The probability that a diffuse sample passes to the back: in proportion
// to the two albedos, at least 5% for each that is not 0.
VKP_FN float diffuseTransmissionProbability(MetallicRoughness p) {
    if (!hasDiffuseTransmission(p)) return 0.0f;
    vec2 a = diffuseAlbedos(p);
    if (!(a.y > 0.0f)) return 0.0f;
    if (!(a.x > 0.0f)) return 1.0f;
    return clamp(a.y / (a.x + a.y), 0.05f, 0.95f);
}

// Each lobe's weight at wo (o.z = cos theta_o), estimated with the Fresnel
// terms at the macro normal (h = n): (specular, diffuse).
VKP_FN vec2 metallicRoughnessLobeWeights(MetallicRoughness p, float cosO) {
    vec3 fd = dielectricLayerFresnel(p, cosO);
    float es = meanComponent(mix(fd, metalFresnel(p, cosO), p.metallic));
    vec2 a = diffuseAlbedos(p);
    float ed = (1.0f - p.metallic) * (1.0f - largestComponent(fd)) * (a.x + a.y);
    return vec2(es, ed);
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
    bool diffuse =
        p.metallic < 1.0f &&
        (largestComponent(p.baseColor) > 0.0f ||
         (hasDiffuseTransmission(p) && largestComponent(p.diffuseTransmissionColor) > 0.0f)) &&
        (largestComponent(p.specularF0) < 1.0f || p.specularF90 < 1.0f);
    if (!diffuse) return specular ? 1.0f : 0.0f;
    if (!specular) return 0.0f;
    vec2 e = metallicRoughnessLobeWeights(p, cosO);
    if (!(e.x + e.y > 0.0f)) return 0.5f;
    return clamp(e.x / (e.x + e.y), 0.05f, 0.95f);
}

// f |cos wi| for o in the upper hemisphere and i in it (or below it, with
// diffuse transmission); the diffuse lobe alone when the specular one is a
// delta.
VKP_FN vec3 evalMetallicRoughnessUpper(MetallicRoughness p, vec3 o, vec3 i) {
    if (hasDiffuseTransmission(p) && i.z < 0.0f) {
        vec3 r = vec3(i.x, i.y, -i.z);  // the mirror image above
        vec3 fr = dielectricLayerFresnel(p, dot(o, normalize(o + r)));
        return ((1.0f - p.metallic) * (1.0f - largestComponent(fr)) * p.diffuseTransmission *
                (r.z * VKP_INV_PI)) *
               p.diffuseTransmissionColor;
    }
    vec3 h = normalize(o + i);
    float c = dot(o, h);
    vec3 fd = dielectricLayerFresnel(p, c);
    vec3 f =
        ((1.0f - p.metallic) * (1.0f - largestComponent(fd)) * (i.z * VKP_INV_PI)) * p.baseColor;
    if (hasDiffuseTransmission(p)) f *= 1.0f - p.diffuseTransmission;
    if (microfacetIsSmooth(p.alpha)) return f;
    // D G2 / (4 zo zi) x zi = D zi / (2 (zi Lo + zo Li)), as evalConductor.
    float d = i.z * ggxStretchedLength(o, p.alpha) + o.z * ggxStretchedLength(i, p.alpha);
    float specular = ggxD(h, p.alpha) * i.z / (2.0f * d);
    vec3 fresnel = metallicRoughnessSpecularFresnel(p, c);
    if (p.multipleScattering > 0.0f)
        fresnel *= vec3(1.0f) + metallicRoughnessSpecularFresnel(p, 1.0f) * p.multipleScattering;
    return f + fresnel * specular;
}

// The mixture's density of i for o (upper hemisphere, pSpec from
// specularProbability; i below only with diffuse transmission).
VKP_FN float metallicRoughnessPdfUpper(MetallicRoughness p, vec3 o, vec3 i, float pSpec) {
    float pass = diffuseTransmissionProbability(p);
    if (hasDiffuseTransmission(p) && i.z < 0.0f)
        return (1.0f - pSpec) * pass * cosineHemispherePdf(-i.z);
    float pdf = (1.0f - pSpec) * cosineHemispherePdf(i.z);
    if (hasDiffuseTransmission(p)) pdf *= 1.0f - pass;
    if (microfacetIsSmooth(p.alpha)) return pdf;
    vec3 h = normalize(o + i);
    // D_wo(h) / (4 wo.h) = D / (2 (zo + Lo)), the conductor's reflection density.
    return pdf + pSpec * ggxD(h, p.alpha) / (2.0f * (o.z + ggxStretchedLength(o, p.alpha)));
}

// The base material alone. u picks the direction within the lobe, uc the lobe.
VKP_FN BsdfSample sampleMetallicRoughnessBase(MetallicRoughness p, vec3 wo, vec2 u, float uc) {
    if (wo.z == 0.0f) return invalidBsdfSample();
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    float pSpec = specularProbability(p, o.z);
    vec3 i;
    bool passes = false;
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
        // (uc - pSpec) / (1 - pSpec) is uniform: its low part passes.
        passes = hasDiffuseTransmission(p) &&
                 uc - pSpec < diffuseTransmissionProbability(p) * (1.0f - pSpec);
        if (passes) i.z = -i.z;
    }
    // Reflected below the macro surface: lost, as the conductor's.
    if (passes ? !(i.z < 0.0f) : i.z <= 0.0f) return invalidBsdfSample();
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

// ---- the layers ---------------------------------------------------------------------------

VKP_FN bool hasClearcoat(MetallicRoughness p) {
    return hasFeature(VKP_FEATURE_CLEARCOAT) && p.clearcoat > 0.0f;
}
VKP_FN bool hasSheen(MetallicRoughness p) {
    return hasFeature(VKP_FEATURE_SHEEN) && largestComponent(p.sheenColor) > 0.0f;
}
VKP_FN bool hasLayers(MetallicRoughness p) {
    return hasClearcoat(p) || hasSheen(p);
}

// max(sheenColor) min(1, E): the share of the light the sheen takes from the
// base at wo.
VKP_FN float sheenAlbedo(MetallicRoughness p) {
    if (!hasSheen(p)) return 0.0f;
    return largestComponent(p.sheenColor) * min(p.sheenLobeAlbedo, 1.0f);
}

// clearcoat F_c(c): the share of the light a coat of weight `clearcoat`
// reflects at cosine c (its index 1.5: Schlick's F0 = 0.04).
VKP_FN float clearcoatFresnel(float clearcoat, float c) {
    float x = 1.0f - clamp(c, 0.0f, 1.0f);
    float x2 = x * x;
    return clearcoat * (0.04f + 0.96f * (x2 * x2 * x));
}

// Whether the coat lies on a normal of its own (clearcoatNormalTexture).
VKP_FN bool coatTilted(MetallicRoughness p) {
    return hasClearcoat(p) && p.coatNormal != vec3(0.0f, 0.0f, 1.0f);
}
// A direction of this frame in the coat's (its normal +z), and back: the
// same direction where the coat lies on the shading normal.
VKP_FN vec3 toCoat(MetallicRoughness p, vec3 v) {
    return coatTilted(p) ? frameToLocal(makeFrame(p.coatNormal), v) : v;
}
VKP_FN vec3 fromCoat(MetallicRoughness p, vec3 v) {
    return coatTilted(p) ? frameToWorld(makeFrame(p.coatNormal), v) : v;
}

// clearcoat F_c(cos theta_o): the share of the coat in the mix.
VKP_FN float coatWeight(MetallicRoughness p, float cosO) {
    if (!hasClearcoat(p)) return 0.0f;
    return clearcoatFresnel(p.clearcoat, cosO);
}

// The probabilities of sampling the coat, the sheen and the base at wo:
// 0.9 of them in proportion to each layer's albedo estimate (the coat's
// weight, the sheen's albedo, the base's Fresnel-weighted lobes under both),
// 0.1 shared evenly among the layers present, so that every lobe with f > 0
// keeps a share (the estimates at h = n may be 0 where f is not).
struct LayerChoice {
    float coat;
    float sheen;
    float base;
};
// (cosO to the shading normal, coatCosO to the coat's)
VKP_FN LayerChoice layerChoice(MetallicRoughness p, float cosO, float coatCosO) {
    float fc = coatWeight(p, coatCosO);
    float wc = fc;
    float ws = (1.0f - fc) * sheenAlbedo(p);
    vec2 e = metallicRoughnessLobeWeights(p, cosO);
    float wb = (1.0f - fc) * (1.0f - sheenAlbedo(p)) * (e.x + e.y);
    float present = 1.0f + (hasClearcoat(p) ? 1.0f : 0.0f) + (hasSheen(p) ? 1.0f : 0.0f);
    float sum = wc + ws + wb;
    float scale = sum > 0.0f ? 0.9f / sum : 0.0f;
    float even = (sum > 0.0f ? 0.1f : 1.0f) / present;
    LayerChoice c;
    c.coat = hasClearcoat(p) ? wc * scale + even : 0.0f;
    c.sheen = hasSheen(p) ? ws * scale + even : 0.0f;
    c.base = max(0.0f, 1.0f - c.coat - c.sheen);
    return c;
}
// ... where the coat lies on the shading normal
VKP_FN LayerChoice layerChoice(MetallicRoughness p, float cosO) {
    return layerChoice(p, cosO, cosO);
}

// f |cos wi| of the whole material for o, i in the upper hemisphere, its
// delta lobes (a smooth base's or coat's specular reflection) left out. The
// coat's lobe, F_c and cosine are its own normal's (a normal map of its own
// turns them).
VKP_FN vec3 evalLayeredUpper(MetallicRoughness p, vec3 o, vec3 i) {
    vec3 f = evalMetallicRoughnessUpper(p, o, i);
    if (!hasLayers(p)) return f;
    vec3 oc = toCoat(p, o);
    float fc = coatWeight(p, oc.z);
    f *= (1.0f - fc) * (1.0f - sheenAlbedo(p));
    if (i.z <= 0.0f) return f;  // (what passes: the base's alone)
    if (hasSheen(p))
        f += ((1.0f - fc) * sheenReflection(o, i, p.sheenAlpha) / max(1.0f, p.sheenLobeAlbedo)) *
             p.sheenColor;
    vec3 ic = toCoat(p, i);
    if (hasClearcoat(p) && !microfacetIsSmooth(p.coatAlpha) && oc.z > 0.0f && ic.z > 0.0f) {
        vec3 h = normalize(oc + ic);
        float d =
            ic.z * ggxStretchedLength(oc, p.coatAlpha) + oc.z * ggxStretchedLength(ic, p.coatAlpha);
        f += vec3(fc * ggxD(h, p.coatAlpha) * ic.z / (2.0f * d));
    }
    return f;
}

// The density of i among the non-delta lobes, each weighted by its choice.
VKP_FN float layeredPdfUpper(MetallicRoughness p, vec3 o, vec3 i, LayerChoice c) {
    float pdf = c.base * metallicRoughnessPdfUpper(p, o, i, specularProbability(p, o.z));
    if (i.z <= 0.0f) return pdf;
    if (hasSheen(p)) pdf += c.sheen * uniformHemispherePdf();
    vec3 oc = toCoat(p, o), ic = toCoat(p, i);
    if (hasClearcoat(p) && !microfacetIsSmooth(p.coatAlpha) && oc.z > 0.0f && ic.z > 0.0f) {
        vec3 h = normalize(oc + ic);
        pdf +=
            c.coat * ggxD(h, p.coatAlpha) / (2.0f * (oc.z + ggxStretchedLength(oc, p.coatAlpha)));
    }
    return pdf;
}

// A direction of the layered material: uc picks the layer (and, rescaled, the
// base's lobe), u the direction within it.
VKP_FN BsdfSample sampleLayered(MetallicRoughness p, vec3 o, vec2 u, float uc) {
    vec3 oc = toCoat(p, o);
    LayerChoice c = layerChoice(p, o.z, oc.z);
    vec3 i;
    if (uc < c.coat) {
        if (microfacetIsSmooth(p.coatAlpha)) {
            // The smooth coat's mirror, of reflectance clearcoat F_c (lost
            // where a coat's own normal turns it below the surface).
            BsdfSample s;
            s.direction = fromCoat(p, vec3(-oc.x, -oc.y, oc.z));
            if (!(s.direction.z > 0.0f)) return invalidBsdfSample();
            s.weight = vec3(coatWeight(p, oc.z) / c.coat);
            s.pdf = c.coat;
            s.delta = true;
            s.valid = true;
            s.etaSquared = 1.0f;
            return s;
        }
        vec3 m = sampleGgxVisibleNormal(oc, p.coatAlpha, u);
        float om = dot(oc, m);
        if (om <= 0.0f) return invalidBsdfSample();
        i = fromCoat(p, 2.0f * om * m - oc);
    } else if (uc < c.coat + c.sheen) {
        i = sampleUniformHemisphere(u);
    } else {
        float ub = min((uc - c.coat - c.sheen) / c.base, 0.99999994f);
        BsdfSample s = sampleMetallicRoughnessBase(p, o, u, ub);
        if (!s.valid) return s;
        if (s.delta) {
            // The smooth base's specular reflection, under both layers.
            s.weight *= (1.0f - coatWeight(p, oc.z)) * (1.0f - sheenAlbedo(p)) / c.base;
            s.pdf *= c.base;
            return s;
        }
        i = s.direction;
    }
    // The coat and the sheen reflect: below the surface their samples are lost
    // (the base's that pass were checked by the base).
    if (i.z <= 0.0f && !(uc >= c.coat + c.sheen && i.z < 0.0f)) return invalidBsdfSample();
    float pdf = layeredPdfUpper(p, o, i, c);
    if (!(pdf > 0.0f)) return invalidBsdfSample();
    BsdfSample s;
    s.direction = i;
    s.pdf = pdf;
    s.weight = evalLayeredUpper(p, o, i) / pdf;
    s.delta = false;
    s.valid = true;
    s.etaSquared = 1.0f;
    return s;
}

// ---- the material, two-sided ------------------------------------------------------------

// (Seen from below, the frame is flipped; a coat's own normal faces wo, so
// it flips with it.)
VKP_FN BsdfSample sampleMetallicRoughness(MetallicRoughness p, vec3 wo, vec2 u, float uc) {
    if (!hasLayers(p)) return sampleMetallicRoughnessBase(p, wo, u, uc);
    if (wo.z == 0.0f) return invalidBsdfSample();
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    if (coatTilted(p)) p.coatNormal *= side;
    BsdfSample s = sampleLayered(p, side * wo, u, uc);
    s.direction *= side;
    return s;
}

// (wo and wi on opposite sides: only diffuse transmission joins them)
VKP_FN bool metallicRoughnessSidesJoin(MetallicRoughness p, vec3 wo, vec3 wi) {
    return wo.z * wi.z > 0.0f || (hasDiffuseTransmission(p) && wo.z != 0.0f && wi.z != 0.0f);
}

VKP_FN vec3 evalMetallicRoughness(MetallicRoughness p, vec3 wo, vec3 wi) {
    if (!metallicRoughnessSidesJoin(p, wo, wi)) return vec3(0.0f);
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    if (coatTilted(p)) p.coatNormal *= side;
    return evalLayeredUpper(p, side * wo, side * wi);
}

VKP_FN float metallicRoughnessPdf(MetallicRoughness p, vec3 wo, vec3 wi) {
    if (!metallicRoughnessSidesJoin(p, wo, wi)) return 0.0f;
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    if (!hasLayers(p))
        return metallicRoughnessPdfUpper(p, o, side * wi, specularProbability(p, o.z));
    if (coatTilted(p)) p.coatNormal *= side;
    return layeredPdfUpper(p, o, side * wi, layerChoice(p, o.z, toCoat(p, o).z));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_METALLIC_ROUGHNESS_H
