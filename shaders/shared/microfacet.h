// Microfacet BSDF lobes: the Trowbridge-Reitz (GGX) distribution with the
// height-correlated Smith masking-shadowing term, sampling of its visible
// normals, and from them a rough conductor and a rough dielectric.
//
// BsdfSample and the smooth glass of the delta case are shared/lobes.h's;
// shared/bsdf.h dispatches materials to these lobes.
//
// The lobes scatter once: light that meets the microsurface again is lost.
// Multiple-scattering compensation scales them by a factor of wo alone
// (Conductor::multipleScattering and the others; shared/microfacet_albedo.h
// says how it is made), which leaves sampling and pdfs as they are.
//
// Everything here works in the LOCAL shading frame: the macro-surface normal
// is +z, wo and wi are unit vectors pointing away from the surface (wo toward
// the viewer, wi toward the light or the next vertex), and BsdfSample's
// direction is local too. The material layer turns world directions into
// this frame (frameToLocal) and the sampled one back (frameToWorld).
//
// Roughness is alpha (the material maps alpha = roughness^2), given per axis
// of the frame (alpha.x along s, alpha.y along t); equal values are the
// isotropic distribution. Below VKP_MICROFACET_SMOOTH_ALPHA a lobe is its
// exact delta limit (mirror, smooth glass), never a division by alpha.
#ifndef VKPATH_SHARED_MICROFACET_H
#define VKPATH_SHARED_MICROFACET_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/lobes.h"

// Lobes with max(alpha.x, alpha.y) below this are the delta case: pbrt-v4's
// threshold (TrowbridgeReitzDistribution::EffectivelySmooth), so that scenes
// render alike. At alpha 1e-3 half the microfacet normals lie within 1e-3 rad
// of the normal (GGX: P(tan theta_m < alpha) = 1/2), so half the reflected
// light lies within 2e-3 rad (0.11 degrees, two pixels of a 1000 pixel wide,
// 60 degree view): light sampling would almost never land in the lobe and
// would only add variance. Above it D peaks at 1 / (pi alpha^2) = 3.2e5 and
// every term stays well inside float range.
#define VKP_MICROFACET_SMOOTH_ALPHA 1e-3f

VKP_NAMESPACE_BEGIN

VKP_FN bool microfacetIsSmooth(vec2 alpha) {
    return max(alpha.x, alpha.y) < VKP_MICROFACET_SMOOTH_ALPHA;
}

// ---- Trowbridge-Reitz (GGX) ---------------------------------------------------
// Walter et al. 2007, "Microfacet Models for Refraction through Rough
// Surfaces", eq. 33, anisotropic as in Heitz 2014, "Understanding the
// Masking-Shadowing Function in Microfacet-Based BRDFs" (JCGT 3(2)). With
// cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2 expanded for a
// unit m it is 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2): no tan theta,
// no 1 / cos^4, finite at the horizon.
VKP_FN float ggxD(vec3 m, vec2 alpha) {
    if (m.z <= 0.0f) return 0.0f;
    float e = (m.x * m.x) / (alpha.x * alpha.x) + (m.y * m.y) / (alpha.y * alpha.y) + m.z * m.z;
    return 1.0f / (VKP_PI * alpha.x * alpha.y * e * e);
}

// |w| after stretching the surface by alpha: sqrt(z^2 + ax^2 x^2 + ay^2 y^2).
// Smith's Lambda for GGX (Heitz 2014) is (L / |z| - 1) / 2, so the
// masking terms below are written with L and |z|, which keeps them finite
// and exact at grazing angles where tan theta is infinite.
VKP_FN float ggxStretchedLength(vec3 w, vec2 alpha) {
    vec2 s = alpha * vec2(w.x, w.y);
    return sqrt(w.z * w.z + dot(s, s));
}

// Lambda(w) = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2, written as
// alpha^2 tan^2 / (2 (sqrt(1 + alpha^2 tan^2) + 1)) so that a tiny
// alpha tan theta keeps its precision; infinite at the horizon.
VKP_FN float ggxLambda(vec3 w, vec2 alpha) {
    float z = abs(w.z);
    vec2 s = alpha * vec2(w.x, w.y);
    float s2 = dot(s, s);
    return s2 / (2.0f * z * (ggxStretchedLength(w, alpha) + z));
}

// Masking of one direction, G1 = 1 / (1 + Lambda) = 2 |z| / (|z| + L).
// Lambda depends on |z|, so G1 is the same from below as from above.
VKP_FN float ggxG1(vec3 w, vec2 alpha) {
    float z = abs(w.z);
    return 2.0f * z / (z + ggxStretchedLength(w, alpha));
}

// Height-correlated masking-shadowing, G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
// (Heitz 2014), = 2 |zo| |zi| / (|zi| Lo + |zo| Li). Used for reflection
// and, as pbrt-v4 does, for transmission too (for wo and wi on opposite
// sides the height-correlated term is instead a Beta function,
// B(1 + Lambda(wo), 1 + Lambda(wi)), which is never larger; both are <= G1(wo),
// so neither creates energy).
VKP_FN float ggxG2(vec3 wo, vec3 wi, vec2 alpha) {
    float zo = abs(wo.z);
    float zi = abs(wi.z);
    float d = zi * ggxStretchedLength(wo, alpha) + zo * ggxStretchedLength(wi, alpha);
    return d > 0.0f ? 2.0f * zo * zi / d : 0.0f;
}

// G2 / G1(wo), the weight of every visible-normal sample before Fresnel and
// tints: |zi| (|zo| + Lo) / (|zi| Lo + |zo| Li) <= 1.
VKP_FN float ggxG2OverG1(vec3 wo, vec3 wi, vec2 alpha) {
    float zo = abs(wo.z);
    float zi = abs(wi.z);
    float lo = ggxStretchedLength(wo, alpha);
    float d = zi * lo + zo * ggxStretchedLength(wi, alpha);
    return d > 0.0f ? zi * (zo + lo) / d : 0.0f;
}

// ---- visible normals ------------------------------------------------------------
// The density of microfacet normals m that wo sees (Heitz 2018, "Sampling the
// GGX Distribution of Visible Normals", JCGT 7(4)):
// D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z, here 2 max(0, wo.m) D(m) / (zo + Lo),
// finite even at wo.z = 0. wo must be in the upper hemisphere (wo.z >= 0):
// the lobes below flip a wo from below before they sample.
VKP_FN float ggxVisibleNormalPdf(vec3 wo, vec3 m, vec2 alpha) {
    float om = dot(wo, m);
    if (om <= 0.0f) return 0.0f;
    return 2.0f * om * ggxD(m, alpha) / (wo.z + ggxStretchedLength(wo, alpha));
}

// Samples D_wo by the spherical-cap form of Dupuy and Benyoub 2023, "Sound and
// Robust Sampling of the Visible Normals of GGX": in the
// configuration stretched to alpha = 1 the visible normals of wo are uniform
// on the cap of the unit sphere above the plane z = -wo'.z, shifted by wo'
// (wo' the stretched wo), then unstretched (normals scale by alpha like
// directions do, Heitz 2018). wo.z >= 0.
VKP_FN vec3 sampleGgxVisibleNormal(vec3 wo, vec2 alpha, vec2 u) {
    vec3 v = normalize(vec3(alpha.x * wo.x, alpha.y * wo.y, wo.z));
    float phi = VKP_TWO_PI * u.x;
    // z uniform in (-v.z, 1]: 1 - u.y, not u.y, so that u.y = 0 gives the top.
    float z = (1.0f - u.y) * (1.0f + v.z) - v.z;
    float sinTheta = sqrt(clamp(1.0f - z * z, 0.0f, 1.0f));
    vec3 h = vec3(sinTheta * cos(phi), sinTheta * sin(phi), z) + v;
    return normalize(vec3(alpha.x * h.x, alpha.y * h.y, max(h.z, 0.0f)));
}

// ---- Fresnel ------------------------------------------------------------------------

// Schlick's approximation with a colour F0 (glTF 2.0 Appendix B,
// metal_brdf's fresnel_mix: F0 = base colour). cosTheta = wo.m.
VKP_FN vec3 fresnelSchlick(vec3 f0, float cosTheta) {
    float c = 1.0f - clamp(cosTheta, 0.0f, 1.0f);
    float c2 = c * c;
    return f0 + (vec3(1.0f) - f0) * (c2 * c2 * c);
}

// Complex numbers as vec2 (re, im) for the conductor's Fresnel equations.
VKP_FN vec2 complexMul(vec2 a, vec2 b) {
    return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

VKP_FN vec2 complexDiv(vec2 a, vec2 b) {
    float scale = 1.0f / dot(b, b);
    return vec2(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y) * scale;
}

// The principal square root, by the half-angle formulas: with n = |z|,
// t = sqrt((n + |re|) / 2) and im / (2 t) are the two parts, t going to the
// real one when re >= 0 (no cancellation in either case).
VKP_FN vec2 complexSqrt(vec2 z) {
    float n = length(z);
    if (n == 0.0f) return vec2(0.0f);
    float t1 = sqrt(0.5f * (n + abs(z.x)));
    float t2 = 0.5f * z.y / t1;
    if (z.x >= 0.0f) return vec2(t1, t2);
    return vec2(abs(t2), z.y >= 0.0f ? t1 : -t1);
}

// Unpolarised reflectance of a conductor of complex relative index
// eta + i k for light at cosine cosTheta (clamped to [0, 1]): the Fresnel
// equations with a complex index (PBR 4th ed., section 9.3.6, FrComplex).
VKP_FN float fresnelComplex(float cosTheta, float eta, float k) {
    cosTheta = clamp(cosTheta, 0.0f, 1.0f);
    vec2 n = vec2(eta, k);
    vec2 sin2ThetaT = complexDiv(vec2(1.0f - cosTheta * cosTheta, 0.0f), complexMul(n, n));
    vec2 cosThetaT = complexSqrt(vec2(1.0f, 0.0f) - sin2ThetaT);
    vec2 nCosI = n * cosTheta;
    vec2 nCosT = complexMul(n, cosThetaT);
    vec2 rParallel = complexDiv(nCosI - cosThetaT, nCosI + cosThetaT);
    vec2 rPerpendicular = complexDiv(vec2(cosTheta, 0.0f) - nCosT, vec2(cosTheta, 0.0f) + nCosT);
    return 0.5f * (dot(rParallel, rParallel) + dot(rPerpendicular, rPerpendicular));
}

VKP_FN vec3 fresnelComplex3(float cosTheta, vec3 eta, vec3 k) {
    return vec3(fresnelComplex(cosTheta, eta.x, k.x), fresnelComplex(cosTheta, eta.y, k.y),
                fresnelComplex(cosTheta, eta.z, k.z));
}

// ---- rough conductor ------------------------------------------------------------------
// Cook-Torrance reflection with GGX: f = F(wo.m) D(m) G2 / (4 |zo| |zi|),
// m = normalize(wo + wi) (Walter et al. 2007, eq. 20). wi is sampled from the
// visible normals of wo and reflected about m, so the density is
// D_wo(m) / (4 wo.m) (the half-vector Jacobian, Walter eq. 14) and the weight
// is F G2 / G1(wo). Two-sided like the mirror: a wo below the surface
// reflects below it (the frame is flipped for it).

// Conductor::fresnel: how the reflectance depends on the angle.
#define VKP_FRESNEL_SCHLICK 0u   // Schlick's approximation with f0 (glTF's metals)
#define VKP_FRESNEL_COMPLEX 1u   // the exact Fresnel equations of eta + i k
#define VKP_FRESNEL_CONSTANT 2u  // f0 at every angle (the mirror, roughened by path regularisation)

struct Conductor {
    vec2 alpha;    // GGX roughness along s and t (alpha = roughness^2)
    vec3 f0;       // reflectance at normal incidence (glTF: base colour)
    vec3 eta;      // complex index, real part per RGB channel, relative to the outside
    vec3 k;        // complex index, imaginary part (absorption) per channel
    uint fresnel;  // VKP_FRESNEL_*
    // (1 - E(mu_o)) / E(mu_o) for this wo, E the white lobe's albedo: the lobe
    // is scaled by 1 + F(1) x this (multiple-scattering compensation,
    // shared/microfacet_albedo.h); 0: single scattering
    float multipleScattering;
};

VKP_FN vec3 conductorFresnel(Conductor c, float cosTheta) {
    if (c.fresnel == VKP_FRESNEL_COMPLEX) return fresnelComplex3(cosTheta, c.eta, c.k);
    if (c.fresnel == VKP_FRESNEL_CONSTANT) return c.f0;
    return fresnelSchlick(c.f0, cosTheta);
}

// The factor multiple-scattering compensation puts on the conductor's lobe,
// 1 + F(1) (1 - E) / E (Turquin 2019, eq. 8 with F0 the Fresnel term at
// normal incidence): exactly 1 / E for a white conductor.
VKP_FN vec3 conductorCompensation(Conductor c) {
    if (!(c.multipleScattering > 0.0f)) return vec3(1.0f);
    return vec3(1.0f) + conductorFresnel(c, 1.0f) * c.multipleScattering;
}

VKP_FN BsdfSample sampleConductor(Conductor c, vec3 wo, vec2 u) {
    if (wo.z == 0.0f) return invalidBsdfSample();
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    BsdfSample s;
    s.delta = false;
    s.valid = true;
    s.etaSquared = 1.0f;
    if (microfacetIsSmooth(c.alpha)) {
        // The mirror: probability 1, weight F of the macro normal.
        s.direction = side * vec3(-o.x, -o.y, o.z);
        s.weight = conductorFresnel(c, o.z);
        s.pdf = 1.0f;
        s.delta = true;
        return s;
    }
    vec3 m = sampleGgxVisibleNormal(o, c.alpha, u);
    float om = dot(o, m);
    vec3 i = 2.0f * om * m - o;
    // Reflected below the macro surface: a path the single-scattering model
    // loses (the energy multiple scattering would return).
    if (om <= 0.0f || i.z <= 0.0f) return invalidBsdfSample();
    s.direction = side * i;
    // D_wo(m) / (4 wo.m) = D / (2 (zo + Lo)).
    s.pdf = ggxD(m, c.alpha) / (2.0f * (o.z + ggxStretchedLength(o, c.alpha)));
    s.weight = conductorFresnel(c, om) * ggxG2OverG1(o, i, c.alpha) * conductorCompensation(c);
    return s;
}

// f * |cos wi| = F D G2 / (4 zo) = F D zi / (2 (zi Lo + zo Li)); 0 for wo, wi
// on different sides and for the delta case.
VKP_FN vec3 evalConductor(Conductor c, vec3 wo, vec3 wi) {
    if (microfacetIsSmooth(c.alpha) || wo.z * wi.z <= 0.0f) return vec3(0.0f);
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    vec3 i = side * wi;
    vec3 m = normalize(o + i);
    float d = i.z * ggxStretchedLength(o, c.alpha) + o.z * ggxStretchedLength(i, c.alpha);
    return conductorFresnel(c, dot(o, m)) * (ggxD(m, c.alpha) * i.z / (2.0f * d)) *
           conductorCompensation(c);
}

VKP_FN float conductorPdf(Conductor c, vec3 wo, vec3 wi) {
    if (microfacetIsSmooth(c.alpha) || wo.z * wi.z <= 0.0f) return 0.0f;
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    vec3 o = side * wo;
    vec3 m = normalize(o + side * wi);
    return ggxD(m, c.alpha) / (2.0f * (o.z + ggxStretchedLength(o, c.alpha)));
}

// ---- rough dielectric -------------------------------------------------------------------
// Walter et al. 2007 (and PBR 4th ed., section 9.7). The normal +z points to
// the outside; ior is n_inside / n_outside, as for the smooth glass. A wo
// below the surface is handled by flipping the frame (wo, wi -> -wo, -wi),
// which turns the inside into the outside and the relative index into
// 1 / ior: D, Lambda and G depend only on squares and |z|, so the lobe from
// below is the same formula. In that frame eta = n(wi side) / n(wo side)
// for transmission, the lobes.h convention.
//
// A visible normal m is sampled; reflection is chosen with probability
// F(wo.m), refraction through m otherwise. pdf is the solid-angle density of
// the whole procedure (the choice's probability included, as the smooth
// glass's pdf is F or 1 - F):
//   reflection:   F D_wo(m) / (4 wo.m)                           (Walter eq. 14)
//   transmission: (1 - F) D_wo(m) eta^2 |wi.m| / (wo.m + eta wi.m)^2 (Walter eq. 17)
// with m the generalised half vector normalize(wo + eta wi) for transmission
// (Walter eq. 16). The transmitted f is Walter's eq. 21 for radiance, which
// carries the 1 / eta^2 of the smooth glass (PBR 4th ed., section 9.5.2): the
// weight is T G2 / (G1 eta^2), BsdfSample::etaSquared = eta^2, and
// f(wo, wi) / n(wo side)^2 = f(wi, wo) / n(wi side)^2 (Veach's thesis, chapter 5).
//
// A thin wall (glTF's transmission without a volume, RoughDielectric::thin)
// has air on both sides: the index is ior from either side, and what passes
// is the reflection lobe mirrored through the surface (wi's z negated), so
// the light leaves unbent on average, blurred by the roughness (the
// extension's thin-walled BTDF). Reflection keeps F, transmission 1 - F, of
// the one GGX reflection lobe: the white thin wall's albedo is the
// conductor's, and its compensation the conductor's table.

struct RoughDielectric {
    vec2 alpha;          // GGX roughness along s and t (alpha = roughness^2)
    float ior;           // n_inside / n_outside; the inside is -z
    vec3 reflectance;    // tint of reflected light (1 for physical glass)
    vec3 transmittance;  // tint of refracted light
    // (1 - E) / E for this wo, E the white lobe's flux albedo from wo's side:
    // reflection and refraction are scaled by 1 / E (multiple-scattering
    // compensation, shared/microfacet_albedo.h); 0: single scattering
    float multipleScattering;
    bool thin;  // a thin wall (above)
};

// u picks the visible normal, uc the reflect/refract choice.
VKP_FN BsdfSample sampleRoughDielectric(RoughDielectric d, vec3 wo, vec2 u, float uc) {
    if (d.thin && microfacetIsSmooth(d.alpha))
        return sampleThinDielectric(d.reflectance, d.transmittance, d.ior, vec3(0.0f, 0.0f, 1.0f),
                                    wo, uc);
    // Index 1 refracts every microfacet straight through (a delta however
    // rough), so it is the smooth glass too, as in pbrt-v4.
    if (!d.thin && (microfacetIsSmooth(d.alpha) || d.ior == 1.0f))
        return sampleDielectric(d.reflectance, d.transmittance, d.ior, vec3(0.0f, 0.0f, 1.0f), wo,
                                uc);
    if (wo.z == 0.0f) return invalidBsdfSample();
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    float eta = d.thin || wo.z > 0.0f ? d.ior : 1.0f / d.ior;
    vec3 o = side * wo;
    vec3 m = sampleGgxVisibleNormal(o, d.alpha, u);
    float om = dot(o, m);
    if (om <= 0.0f) return invalidBsdfSample();
    float fresnel = fresnelDielectric(om, eta);
    float visiblePdf = ggxVisibleNormalPdf(o, m, d.alpha);

    BsdfSample s;
    s.delta = false;
    s.valid = true;
    if (uc < fresnel) {
        vec3 i = 2.0f * om * m - o;
        if (i.z <= 0.0f) return invalidBsdfSample();
        s.direction = side * i;
        s.pdf = fresnel * visiblePdf / (4.0f * om);
        s.weight = d.reflectance * (ggxG2OverG1(o, i, d.alpha) * (1.0f + d.multipleScattering));
        s.etaSquared = 1.0f;
        return s;
    }
    if (d.thin) {
        // The reflection, mirrored through the wall.
        vec3 r = 2.0f * om * m - o;
        if (r.z <= 0.0f) return invalidBsdfSample();
        s.direction = side * vec3(r.x, r.y, -r.z);
        s.pdf = (1.0f - fresnel) * visiblePdf / (4.0f * om);
        s.weight = d.transmittance * (ggxG2OverG1(o, r, d.alpha) * (1.0f + d.multipleScattering));
        s.etaSquared = 1.0f;
        return s;
    }
    // Snell's law about m; uc >= F means F < 1, so no total internal reflection.
    float sin2T = (1.0f - om * om) / (eta * eta);
    float cosT = sqrt(max(0.0f, 1.0f - sin2T));
    vec3 i = normalize(-o / eta + (om / eta - cosT) * m);
    // Refracted through a steep microfacet back to wo's side: lost (single scattering).
    if (i.z >= 0.0f) return invalidBsdfSample();
    float im = dot(i, m);
    float denom = om + eta * im;
    s.direction = side * i;
    s.pdf = (1.0f - fresnel) * visiblePdf * eta * eta * abs(im) / (denom * denom);
    s.weight = d.transmittance *
               (ggxG2OverG1(o, i, d.alpha) * (1.0f + d.multipleScattering) / (eta * eta));
    s.etaSquared = eta * eta;
    return s;
}

// The half vector of wo and wi in the flipped frame (o.z > 0) and the
// relative index eta; m.z > 0. Returns false where no microfacet joins them
// with wo and wi on its correct sides (Walter's chi+ terms).
VKP_FN bool roughDielectricHalfVector(vec3 o, vec3 i, float eta, VKP_OUT(vec3) m) {
    m = vec3(0.0f, 0.0f, 1.0f);
    bool reflection = i.z > 0.0f;
    vec3 h = reflection ? o + i : o + eta * i;
    float len2 = dot(h, h);
    if (!(len2 > 0.0f)) return false;
    m = h * inversesqrt(len2);
    if (m.z < 0.0f) m = -m;
    if (m.z == 0.0f) return false;
    float om = dot(o, m);
    float im = dot(i, m);
    return reflection ? (om > 0.0f && im > 0.0f) : (om > 0.0f && im < 0.0f);
}

// The thin wall's lobe at o (o.z > 0) and i (either side; its mirror r
// above the surface): the GGX reflection's f |cos| of r, and its Fresnel
// term, F for reflection, 1 - F for transmission.
struct ThinWallLobe {
    float reflection;  // D G2 / (4 o.z), compensated
    float visiblePdf;  // D_wo(m) / (4 wo.m): the density of r
    float fresnel;     // F or 1 - F, as i reflects or passes
};
VKP_FN ThinWallLobe thinWallLobe(RoughDielectric d, vec3 o, vec3 i) {
    vec3 r = vec3(i.x, i.y, abs(i.z));
    vec3 m = normalize(o + r);
    float om = dot(o, m);
    float fresnel = fresnelDielectric(om, d.ior);
    ThinWallLobe l;
    l.reflection =
        ggxD(m, d.alpha) * ggxG2(o, r, d.alpha) * (1.0f + d.multipleScattering) / (4.0f * o.z);
    l.visiblePdf = ggxVisibleNormalPdf(o, m, d.alpha) / (4.0f * om);
    l.fresnel = i.z > 0.0f ? fresnel : 1.0f - fresnel;
    return l;
}

// f * |cos wi|, reflection and transmission; 0 in the delta case.
VKP_FN vec3 evalRoughDielectric(RoughDielectric d, vec3 wo, vec3 wi) {
    if (microfacetIsSmooth(d.alpha) || (!d.thin && d.ior == 1.0f) || wo.z == 0.0f || wi.z == 0.0f)
        return vec3(0.0f);
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    if (d.thin) {
        ThinWallLobe l = thinWallLobe(d, side * wo, side * wi);
        return (side * wi.z > 0.0f ? d.reflectance : d.transmittance) * (l.fresnel * l.reflection);
    }
    float eta = wo.z > 0.0f ? d.ior : 1.0f / d.ior;
    vec3 o = side * wo;
    vec3 i = side * wi;
    vec3 m;
    if (!roughDielectricHalfVector(o, i, eta, m)) return vec3(0.0f);
    float om = dot(o, m);
    float fresnel = fresnelDielectric(om, eta);
    float dm = ggxD(m, d.alpha);
    float g2 = ggxG2(o, i, d.alpha) * (1.0f + d.multipleScattering);
    if (i.z > 0.0f) return d.reflectance * (fresnel * dm * g2 / (4.0f * o.z));
    float im = dot(i, m);
    float denom = om + eta * im;
    // Walter eq. 21 times |cos wi|, for radiance (n on wo's side is 1 here).
    return d.transmittance * ((1.0f - fresnel) * dm * g2 * abs(im) * om / (o.z * denom * denom));
}

VKP_FN float roughDielectricPdf(RoughDielectric d, vec3 wo, vec3 wi) {
    if (microfacetIsSmooth(d.alpha) || (!d.thin && d.ior == 1.0f) || wo.z == 0.0f || wi.z == 0.0f)
        return 0.0f;
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    if (d.thin) {
        ThinWallLobe l = thinWallLobe(d, side * wo, side * wi);
        return l.fresnel * l.visiblePdf;
    }
    float eta = wo.z > 0.0f ? d.ior : 1.0f / d.ior;
    vec3 o = side * wo;
    vec3 i = side * wi;
    vec3 m;
    if (!roughDielectricHalfVector(o, i, eta, m)) return 0.0f;
    float om = dot(o, m);
    float fresnel = fresnelDielectric(om, eta);
    float visiblePdf = ggxVisibleNormalPdf(o, m, d.alpha);
    if (i.z > 0.0f) return fresnel * visiblePdf / (4.0f * om);
    float im = dot(i, m);
    float denom = om + eta * im;
    return (1.0f - fresnel) * visiblePdf * eta * eta * abs(im) / (denom * denom);
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_MICROFACET_H
