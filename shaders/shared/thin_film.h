// The Fresnel reflectance of a surface under a thin film
// (KHR_materials_iridescence): Belcour and Barla 2017, "A Practical
// Extension to Microfacet Theory for the Modeling of Varying Iridescence",
// in the approximation the extension's implementation notes give:
//
// - two interfaces, outside -> film (index filmIor) and film -> base (the
//   base's index recovered from its F0, per channel, as if its extinction
//   were 0), each reflecting by Schlick's approximation at its angle (theta1
//   outside, theta2 inside the film by Snell's law), phases 0 or pi by which
//   side is denser, polarisation ignored;
// - the Airy sum of the film's multiple reflections integrated against the
//   RGB sensitivities in Fourier space: the DC term R12 + T121^2 R23 /
//   (1 - R12 R23) and the first two harmonics of the optical path
//   difference 2 filmIor d cos theta2 (Belcour and Barla's section 4), the
//   sensitivities their Gaussian fit of CIE 1931 XYZ, converted to linear
//   Rec. 709 RGB (the extension's constants, which are measured data).
//
// The result is clamped to [0, 1], so that no film reflects more than
// arrives (the Fourier approximation may overshoot by a few thousandths).
#ifndef VKPATH_SHARED_THIN_FILM_H
#define VKPATH_SHARED_THIN_FILM_H

#include "shared/compat.h"
#include "shared/constants.h"

VKP_NAMESPACE_BEGIN

// Schlick's reflectance of normal-incidence reflectance f0 at cosine c.
VKP_FN vec3 thinFilmSchlick(vec3 f0, float c) {
    float x = 1.0f - clamp(c, 0.0f, 1.0f);
    float x2 = x * x;
    return f0 + (vec3(1.0f) - f0) * (x2 * x2 * x);
}

// The reflectance at normal incidence between indices n1 and n2.
VKP_FN float normalReflectance(float n1, float n2) {
    float r = (n1 - n2) / (n1 + n2);
    return r * r;
}

// The sensitivities' response to the harmonic of optical path difference
// `opd` (nm) shifted by phase `shift`, per RGB channel (the extension's
// evalSensitivity: Gaussians in frequency, XYZ to linear Rec. 709).
VKP_FN vec3 thinFilmSensitivity(float opd, vec3 shift) {
    float phase = VKP_TWO_PI * opd * 1.0e-9f;
    vec3 value = vec3(5.4856e-13f, 4.4201e-13f, 5.2481e-13f);
    vec3 position = vec3(1.6810e+06f, 1.7953e+06f, 2.2084e+06f);
    vec3 variance = vec3(4.3278e+09f, 9.3046e+09f, 6.6121e+09f);
    vec3 xyz = value * sqrt(VKP_TWO_PI * variance) * cos(position * phase + shift) *
               exp(-(phase * phase) * variance);
    xyz.x += 9.7470e-14f * sqrt(VKP_TWO_PI * 4.5282e+09f) * cos(2.2399e+06f * phase + shift.x) *
             exp(-4.5282e+09f * (phase * phase));
    xyz *= 1.0f / 1.0685e-7f;
    return vec3(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z,
                -0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z,
                0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z);
}

// The reflectance of a base of normal-incidence reflectance baseF0 (per
// channel) under a film of index filmIor and thickness `thickness` (nm), in
// a medium of index outsideIor, at cosine cosTheta1 to the microfacet normal.
VKP_FN vec3 thinFilmFresnel(float outsideIor, float filmIor, float thickness, float cosTheta1,
                            vec3 baseF0) {
    // Inside the film (Snell's law); total internal reflection: the film reflects all.
    float ratio = outsideIor / filmIor;
    float sin2Theta2 = ratio * ratio * (1.0f - cosTheta1 * cosTheta1);
    if (sin2Theta2 >= 1.0f) return vec3(1.0f);
    float cosTheta2 = sqrt(1.0f - sin2Theta2);
    // The first interface, outside -> film.
    float r12 = thinFilmSchlick(vec3(normalReflectance(filmIor, outsideIor)), cosTheta1).x;
    float t121 = 1.0f - r12;
    float phi12 = filmIor < outsideIor ? VKP_PI : 0.0f;
    float phi21 = VKP_PI - phi12;
    // The second, film -> base; the base's index from its F0 (guarded below 1).
    vec3 root = sqrt(min(baseF0 + vec3(1e-4f), vec3(0.9999f)));
    vec3 baseIor = (vec3(1.0f) + root) / (vec3(1.0f) - root);
    vec3 r23 = thinFilmSchlick(
        vec3(normalReflectance(baseIor.x, filmIor), normalReflectance(baseIor.y, filmIor),
             normalReflectance(baseIor.z, filmIor)),
        cosTheta2);
    vec3 phi23 = vec3(baseIor.x < filmIor ? VKP_PI : 0.0f, baseIor.y < filmIor ? VKP_PI : 0.0f,
                      baseIor.z < filmIor ? VKP_PI : 0.0f);
    vec3 phi = vec3(phi21) + phi23;
    float opd = 2.0f * filmIor * thickness * cosTheta2;
    // The Airy sum: its mean and first two harmonics.
    vec3 r123 = clamp(r12 * r23, vec3(1e-5f), vec3(0.9999f));
    vec3 r123Root = sqrt(r123);
    vec3 rs = (t121 * t121) * r23 / (vec3(1.0f) - r123);
    vec3 reflectance = vec3(r12) + rs;
    vec3 harmonic = rs - vec3(t121);
    for (int m = 1; m <= 2; ++m) {
        harmonic *= r123Root;
        reflectance += harmonic * (2.0f * thinFilmSensitivity(float(m) * opd, float(m) * phi));
    }
    return clamp(reflectance, vec3(0.0f), vec3(1.0f));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_THIN_FILM_H
