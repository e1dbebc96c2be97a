// Warping uniform numbers in [0, 1)^2 to directions and points, each with the
// density it samples. Directions in a local frame have the normal along +z.
#ifndef VKPATH_SHARED_SAMPLING_H
#define VKPATH_SHARED_SAMPLING_H

#include "shared/compat.h"
#include "shared/constants.h"

VKP_NAMESPACE_BEGIN

// An orthonormal frame around unit n, continuous except where n.z = -1
// exactly handled by the sign: Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 6(1), 2017 (listing 3).
struct Frame {
    vec3 s;
    vec3 t;
    vec3 n;
};

VKP_FN Frame makeFrame(vec3 n) {
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.s = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = vec3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

VKP_FN vec3 frameToWorld(Frame f, vec3 local) {
    return local.x * f.s + local.y * f.t + local.z * f.n;
}

VKP_FN vec3 frameToLocal(Frame f, vec3 world) {
    return vec3(dot(world, f.s), dot(world, f.t), dot(world, f.n));
}

// cos(a) and sin(a) for |a| <= pi / 4, the range sampleConcentricDisk needs,
// with no range reduction: the minimax polynomials of Cephes' cosf and sinf
// for that interval (Moshier, "Methods and Programs for Mathematical
// Functions", 1989; Cephes Math Library, single precision), within one ulp
// of the correctly rounded values (Sampling.QuarterPiCosineAndSineWithinOneUlp),
// cheaper than a libm call with its range reduction (docs/BENCHMARKS.md,
// "What each part of its design buys").
VKP_FN vec2 cosSinQuarterPi(float a) {
    float a2 = a * a;
    float c =
        1.0f - 0.5f * a2 +
        a2 * a2 *
            (4.166664568298827e-2f + a2 * (-1.388731625493765e-3f + a2 * 2.443315711809948e-5f));
    float s = a + a * a2 * (-1.6666654611e-1f + a2 * (8.3321608736e-3f + a2 * -1.9515295891e-4f));
    return vec2(c, s);
}

// Shirley and Chiu's concentric map of the square to the unit disk ("A
// Low Distortion Map Between Disk and Square", JGT 2(3), 1997): keeps
// stratification and has no singular corner. Each half of the square maps
// to a wedge of angles within pi / 4 of an axis: x (angle a) or y (pi / 2 -
// a, whose cosine and sine are a's sine and cosine).
VKP_FN vec2 sampleConcentricDisk(vec2 u) {
    vec2 p = 2.0f * u - vec2(1.0f);
    if (p.x == 0.0f && p.y == 0.0f) return vec2(0.0f);
    if (abs(p.x) > abs(p.y)) return p.x * cosSinQuarterPi((VKP_PI / 4.0f) * (p.y / p.x));
    vec2 cs = cosSinQuarterPi((VKP_PI / 4.0f) * (p.x / p.y));
    return p.y * vec2(cs.y, cs.x);
}

// Malley's method: the disk lifted to the hemisphere gives density cos / pi.
VKP_FN vec3 sampleCosineHemisphere(vec2 u) {
    vec2 d = sampleConcentricDisk(u);
    float z = sqrt(max(0.0f, 1.0f - dot(d, d)));
    return vec3(d.x, d.y, z);
}

VKP_FN float cosineHemispherePdf(float cosTheta) {
    return max(cosTheta, 0.0f) * VKP_INV_PI;
}

VKP_FN vec3 sampleUniformSphere(vec2 u) {
    float z = 1.0f - 2.0f * u.x;
    float r = sqrt(max(0.0f, 1.0f - z * z));
    float phi = VKP_TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

VKP_FN float uniformSpherePdf() {
    return VKP_INV_FOUR_PI;
}

VKP_FN vec3 sampleUniformHemisphere(vec2 u) {
    float z = u.x;
    float r = sqrt(max(0.0f, 1.0f - z * z));
    float phi = VKP_TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

VKP_FN float uniformHemispherePdf() {
    return VKP_INV_TWO_PI;
}

// ---- spheres as lights: sampling the cone of directions they subtend -------
// From a point outside the sphere, directions are drawn uniformly in the cone
// (density 1 / (2 pi (1 - cos theta_max))). 1 - cos theta_max is evaluated as
// sin^2 / (1 + cos) so that a tiny or distant sphere (sin^2 ~ 1e-12) keeps its
// precision instead of cancelling to zero (cf. pbrt-v4, Sphere::Sample, which
// switches to a Taylor expansion for the same reason).
struct SphereCone {
    float cosThetaMax;
    float oneMinusCosThetaMax;
    bool inside;  // the point is inside (or on) the sphere: the cone is undefined
};

VKP_FN SphereCone sphereCone(vec3 center, float radius, vec3 p) {
    SphereCone cone;
    vec3 d = center - p;
    float dist2 = dot(d, d);
    float r2 = radius * radius;
    cone.inside = dist2 <= r2;
    float sin2 = min(r2 / dist2, 1.0f);
    cone.cosThetaMax = sqrt(max(0.0f, 1.0f - sin2));
    cone.oneMinusCosThetaMax = sin2 / (1.0f + cone.cosThetaMax);
    return cone;
}

VKP_FN float sphereConePdf(SphereCone cone) {
    return 1.0f / (VKP_TWO_PI * cone.oneMinusCosThetaMax);
}

// A direction in the cone around the unit axis toward the centre.
VKP_FN vec3 sampleSphereCone(SphereCone cone, vec3 axis, vec2 u) {
    // cos theta uniform in [cosThetaMax, 1], written as 1 - u (1 - cosThetaMax)
    // so small cones lose no precision.
    float oneMinusCos = u.x * cone.oneMinusCosThetaMax;
    float cosTheta = 1.0f - oneMinusCos;
    float sinTheta = sqrt(max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
    float phi = VKP_TWO_PI * u.y;
    Frame f = makeFrame(axis);
    return frameToWorld(f, vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta));
}

// ---- triangles as lights: uniform by area ------------------------------------
// Barycentrics (b1, b2) uniform over the triangle (pbrt-v4's square-root
// parameterisation: b0 = 1 - sqrt(u0), b1 = u1 sqrt(u0)).
VKP_FN vec2 sampleTriangleBarycentrics(vec2 u) {
    float s = sqrt(u.x);
    return vec2(1.0f - s, u.y * s);  // weights of vertices 0 and 1; vertex 2 gets the rest
}

VKP_FN vec3 triangleArea3(vec3 p0, vec3 p1, vec3 p2) {
    return 0.5f * cross(p1 - p0, p2 - p0);
}

// Density in solid angle at point `p` of area-uniform samples on a surface of
// area `area`, for a sample at distance^2 `dist2` whose surface normal makes
// cosine `cosLight` with the direction back to p.
VKP_FN float areaToSolidAnglePdf(float area, float dist2, float cosLight) {
    float c = abs(cosLight);
    return c > 0.0f ? dist2 / (c * area) : 0.0f;
}

// Power heuristic with beta = 2 (Veach's thesis, section 9.2.4), written as
// 1 / (1 + (b/a)^2) so that huge densities (a 1e20 pdf squares to infinity)
// still give 1 instead of NaN.
VKP_FN float powerHeuristic(float pdfA, float pdfB) {
    if (!(pdfA > 0.0f)) return 0.0f;
    float r = pdfB / pdfA;
    return 1.0f / (1.0f + r * r);
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_SAMPLING_H
