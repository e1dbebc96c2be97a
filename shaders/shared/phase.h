// The Henyey-Greenstein phase function (Henyey and Greenstein, "Diffuse
// radiation in the galaxy", ApJ 93, 1941): how a medium's particles scatter
// light, its density over the sphere of outgoing directions and its sampling.
// The convention is the one glTF's KHR_materials_volume_scatter, pbrt-v4 and
// Mitsuba 3 share: wo points back along the arriving ray, so
//
//   p(wo, wi) = (1 - g^2) / (4 pi (1 + g^2 + 2 g dot(wo, wi))^(3/2))
//
// and g > 0 scatters forward (wi near -wo), g < 0 back, g = 0 is isotropic.
// The phase function is its own sampling density: a sample's weight is 1.
#ifndef VKPATH_SHARED_PHASE_H
#define VKPATH_SHARED_PHASE_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/sampling.h"

// Below this |g| the phase function is sampled as isotropic: the inversion
// below divides by g, and at |g| < 1e-3 the lobe differs from the uniform
// sphere by under 0.3% of its value anywhere.
#define VKP_HG_ISOTROPIC 1e-3f

VKP_NAMESPACE_BEGIN

// p(wo, wi) for cosWoWi = dot(wo, wi), |g| < 1.
VKP_FN float henyeyGreenstein(float cosWoWi, float g) {
    if (abs(g) < VKP_HG_ISOTROPIC) return 0.25f * VKP_INV_PI;
    float denominator = max(1.0f + g * g + 2.0f * g * cosWoWi, 1e-12f);
    return (1.0f - g * g) / (4.0f * VKP_PI * denominator * sqrt(denominator));
}

// A direction wi of density henyeyGreenstein(dot(wo, wi), g) from u in
// [0, 1)^2. The cosine of the angle between the ray's travel (-wo) and wi
// inverts the lobe's distribution in closed form: cos = (1 + g^2 - ((1 - g^2)
// / (1 - g + 2 g u))^2) / (2 g), e.g. Pharr, Jakob and Humphreys, "Physically
// Based Rendering", 4th ed., section 11.3.1.
VKP_FN vec3 sampleHenyeyGreenstein(vec3 wo, float g, vec2 u) {
    float cosTheta;
    if (abs(g) < VKP_HG_ISOTROPIC) {
        cosTheta = 1.0f - 2.0f * u.x;
    } else {
        float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.x);
        cosTheta = (1.0f + g * g - s * s) / (2.0f * g);
    }
    cosTheta = clamp(cosTheta, -1.0f, 1.0f);
    float sinTheta = sqrt(max(0.0f, 1.0f - cosTheta * cosTheta));
    float phi = 2.0f * VKP_PI * u.y;
    Frame f = makeFrame(-wo);
    return normalize(frameToWorld(f, vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta)));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_PHASE_H
