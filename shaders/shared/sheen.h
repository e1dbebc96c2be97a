// The sheen lobe of KHR_materials_sheen: the back-scattering of a layer of
// fibres standing on the surface (velvet, cloth). Its implementation notes
// (non-normative) give the lobe:
//
//   f_sheen = sheenColor D(h) G / (4 |n.l| |n.v|)
//   D(h)    = (2 + 1 / alpha) sin(theta_h)^(1 / alpha) / (2 pi)
//   G       = 1 / (1 + Lambda(v) + Lambda(l))
//
// with alpha = sheenRoughness^2, D the "Charlie" distribution of Estevez and
// Kulla 2017 ("Production Friendly Microfacet Sheen BRDF") and Lambda their
// fit of its shadowing, exp(L(cos theta)) with L(x) = a / (1 + b x^c) + d x +
// e, its five coefficients interpolated between the fit's two ends by
// (1 - alpha)^2 (below cos 0.5; above it, L mirrored about 0.5 so that Lambda
// stays smooth). The Fresnel factor is 1.
//
// The lobe is sampled uniformly over the hemisphere: D grows toward
// theta_h = 90 degrees, so the lobe's mass lies at grazing angles, where the
// cosine density has none (the weight f |cos| / pdf stays bounded, by 2 pi
// times the largest f |cos|). Directions in the local frame (normal +z), upper
// hemisphere, as in microfacet.h.
#ifndef VKPATH_SHARED_SHEEN_H
#define VKPATH_SHARED_SHEEN_H

#include "shared/compat.h"
#include "shared/constants.h"

VKP_NAMESPACE_BEGIN

// The smallest alpha the lobe takes: sheenRoughness 0 would make D a delta
// on the horizon, which no direction reaches; at alpha 1e-3 D is sin^1000.
#define VKP_SHEEN_MIN_ALPHA 1e-3f

// alpha of sheen roughness `roughness` (KHR_materials_sheen: its square).
VKP_FN float sheenAlpha(float roughness) {
    return max(roughness * roughness, VKP_SHEEN_MIN_ALPHA);
}

VKP_FN float charlieD(float cosH, float alpha) {
    float inverse = 1.0f / alpha;
    float sin2 = max(0.0f, 1.0f - cosH * cosH);
    return (2.0f + inverse) * pow(sin2, 0.5f * inverse) * (0.5f * VKP_INV_PI);
}

// Estevez and Kulla's L(x) (their table 1, the extension's coefficients).
VKP_FN float charlieL(float x, float alpha) {
    float t = (1.0f - alpha) * (1.0f - alpha);
    float a = mix(21.5473f, 25.3245f, t);
    float b = mix(3.82987f, 3.32435f, t);
    float c = mix(0.19823f, 0.16801f, t);
    float d = mix(-1.97760f, -1.27393f, t);
    float e = mix(-4.32054f, -4.85967f, t);
    return a / (1.0f + b * pow(x, c)) + d * x + e;
}

VKP_FN float charlieLambda(float cosTheta, float alpha) {
    float c = min(abs(cosTheta), 1.0f);  // (a normalised vector's z may round above 1)
    return c < 0.5f ? exp(charlieL(c, alpha))
                    : exp(2.0f * charlieL(0.5f, alpha) - charlieL(1.0f - c, alpha));
}

// f |cos theta_i| of the white lobe (sheenColor 1) for o, i in the upper
// hemisphere.
VKP_FN float sheenReflection(vec3 o, vec3 i, float alpha) {
    vec3 h = normalize(o + i);
    return charlieD(h.z, alpha) /
           (4.0f * o.z * (1.0f + charlieLambda(o.z, alpha) + charlieLambda(i.z, alpha)));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_SHEEN_H
