// Dispersion (KHR_materials_dispersion) in an RGB path tracer. Glass whose
// index varies with the wavelength bends each wavelength its own way, so a
// path that meets it follows one wavelength from there on: the path draws
// lambda uniformly in [VKP_WAVELENGTH_MIN, VKP_WAVELENGTH_MAX] nm from a
// number of its own (VKP_DIM_WAVELENGTH: the same at every bounce), keeps it
// (PathState::wavelength), and its throughput takes, once, the weight
//
//   w_c(lambda) = max(0, rgb_c(lambda)) / (integral of max(0, rgb_c) over the range) x range
//
// per channel c, rgb(lambda) the linear sRGB (D65) of a unit spectral line:
// the CIE 1931 colour-matching functions in Wyman, Sloan and Shirley's
// multi-lobe fit ("Simple Analytic Approximations to the CIE XYZ Color
// Matching Functions", JCGT 2(2), 2013, eq. 2) through the XYZ-to-sRGB
// matrix (IEC 61966-2-1). Over the draws E[w] = (1, 1, 1), so a path that
// meets only non-dispersive glass returns its RGB mean unchanged, and white
// light through a prism fans out into colours that sum to white; a spectral
// line's negative sRGB components (outside the gamut) are clipped, which
// desaturates pure spectral colours a little. The index at lambda is the
// extension's Abbe-number form (its README, "Dispersion"):
//
//   n(lambda) = n_d + (n_d - 1) / V_d (523655 / lambda^2 - 1.5168),  V_d = 20 / dispersion
//
// with lambda in nm, n_d the material's index at 587.56 nm (the helium d
// line, where the bracket vanishes).
#ifndef VKPATH_SHARED_SPECTRAL_H
#define VKPATH_SHARED_SPECTRAL_H

#include "shared/compat.h"

// The range of wavelengths drawn, nm: beyond 730 nm the fit's sRGB is below
// 3e-4 of its peak.
#define VKP_WAVELENGTH_MIN 380.0f
#define VKP_WAVELENGTH_MAX 730.0f
// The path's random number for its wavelength, one dimension drawn at no
// bounce (shared/dimensions.h has the bounces' below 2^31; alpha tests use
// 2^31 and above).
#define VKP_DIM_WAVELENGTH 0x7ffffffeu

VKP_NAMESPACE_BEGIN

// One lobe of the fit: a Gaussian of mean mu, of width below it sigma1 and
// above it sigma2.
VKP_FN float cieLobe(float lambda, float mu, float sigma1, float sigma2) {
    float t = (lambda - mu) / (lambda < mu ? sigma1 : sigma2);
    return exp(-0.5f * t * t);
}

// The CIE 1931 2-degree colour-matching functions at lambda nm (Wyman et al.'s fit).
VKP_FN vec3 cieXyz(float lambda) {
    float x = 1.056f * cieLobe(lambda, 599.8f, 37.9f, 31.0f) +
              0.362f * cieLobe(lambda, 442.0f, 16.0f, 26.7f) -
              0.065f * cieLobe(lambda, 501.1f, 20.4f, 26.2f);
    float y = 0.821f * cieLobe(lambda, 568.8f, 46.9f, 40.5f) +
              0.286f * cieLobe(lambda, 530.9f, 16.3f, 31.1f);
    float z = 1.217f * cieLobe(lambda, 437.0f, 11.8f, 36.0f) +
              0.681f * cieLobe(lambda, 459.0f, 26.0f, 13.8f);
    return vec3(x, y, z);
}

// The linear sRGB of a unit spectral line at lambda nm, negative components
// clipped to 0.
VKP_FN vec3 spectralLineRgb(float lambda) {
    vec3 c = cieXyz(lambda);
    vec3 rgb = vec3(3.2404542f * c.x - 1.5371385f * c.y - 0.4985314f * c.z,
                    -0.9692660f * c.x + 1.8760108f * c.y + 0.0415560f * c.z,
                    0.0556434f * c.x - 0.2040259f * c.y + 1.0572252f * c.z);
    return max(rgb, vec3(0.0f));
}

// The range (350 nm) over each channel's integral of spectralLineRgb across
// it, so that the weights below average 1 (the midpoint rule in double over
// 7 x 10^5 points; Spectral.WeightsAverageOneOverTheRange recomputes them).
#define VKP_SPECTRAL_CHANNEL_SCALE vec3(1.986635f, 3.033421f, 3.201655f)

// The wavelength, nm, of a path's uniform number u.
VKP_FN float wavelengthOf(float u) {
    return VKP_WAVELENGTH_MIN + (VKP_WAVELENGTH_MAX - VKP_WAVELENGTH_MIN) * u;
}

// w(lambda): the weight a path's throughput takes when it starts to follow
// wavelength lambda (above).
VKP_FN vec3 spectralWeight(float lambda) {
    return spectralLineRgb(lambda) * VKP_SPECTRAL_CHANNEL_SCALE;
}

// The index at lambda nm of a material of index `ior` at 587.56 nm and
// KHR_materials_dispersion factor `dispersion` (20 / Abbe number).
VKP_FN float dispersedIor(float ior, float dispersion, float lambda) {
    return ior + (ior - 1.0f) * (dispersion / 20.0f) * (523655.0f / (lambda * lambda) - 1.5168f);
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_SPECTRAL_H
