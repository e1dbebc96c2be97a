// The environment map's radiance and its importance sampling.
//
// Radiance: texel (i, j) of a W x H map holds the radiance at its centre,
// map coordinates ((i + 1/2) / W, (j + 1/2) / H), and between centres the
// radiance is interpolated bilinearly from the four nearest (the convention of
// Heckbert, "What are the coordinates of a pixel?", Graphics Gems 1990, and of
// pbrt-v4's Image::Bilerp, appendix B.5: x = u W - 1/2), wrapping around in u
// (longitude is periodic) and clamping in v (within half a texel of a pole,
// the first or last row alone, interpolated in u). Mitsuba 3.9's `envmap`
// emitter interpolates bilinearly too, with the same texel-centred, periodic
// u; its v puts row j at j / (H - 1) (docs/SCENES.md, the Mitsuba table).
//
// Sampling: in proportion to luminance x sin(theta), cell by cell, where
// texel (i, j)'s cell is the rectangle [i/W, (i+1)/W) x [j/H, (j+1)/H) around
// its centre, through an alias table over the cells (shared/alias.h explains
// why not a float marginal/conditional CDF: with a 10^7 sun, whole rows of
// sky fall below one float ulp of the CDF). A cell's weight is the integral
// over it of the bilinear luminance times sin(theta)
// (host/scene/environment_table.cpp), not its own texel's value: the bilinear
// radiance reaches half a texel into the cells of black texels next to bright
// ones, and a cell weighted by its texel alone would leave that energy to BSDF
// sampling. Inside a cell the direction is uniform in (u, v), so the pdf is
// piecewise constant over cells, and the pdf of a direction is its cell's
// probability over the cell's solid angle: exactly the density sampled.
//
// Sampling uses 4 random dimensions: two 32-bit words for the alias table,
// then a point inside the chosen cell:
//   bucket = aliasBucket(bits0, texels); texel = aliasResolve(table[bucket], bucket, bits1);
//   s = envSampleInTexel(info, texel, jitter);
//   pdf = envDirectionPdf(info, table[s.pdfTexel].probability, s.direction);
#ifndef VKPATH_SHARED_ENVIRONMENT_SAMPLING_H
#define VKPATH_SHARED_ENVIRONMENT_SAMPLING_H

#include "shared/alias.h"
#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/environment_map.h"

VKP_NAMESPACE_BEGIN

struct EnvironmentInfo {
    uint width;  // map size in texels
    uint height;
    float strength;     // radiance multiplier
    float cosRotation;  // rotation about +Y applied to the map (world = R * map)
    float sinRotation;
    vec3 color;  // constant radiance when there is no map (width = 0)
};

// Map direction of a world direction (undoing the rotation), and back.
VKP_FN vec3 envWorldToMap(VKP_IN(EnvironmentInfo) info, vec3 d) {
    return vec3(info.cosRotation * d.x - info.sinRotation * d.z, d.y,
                info.sinRotation * d.x + info.cosRotation * d.z);
}

VKP_FN vec3 envMapToWorld(VKP_IN(EnvironmentInfo) info, vec3 d) {
    return vec3(info.cosRotation * d.x + info.sinRotation * d.z, d.y,
                -info.sinRotation * d.x + info.cosRotation * d.z);
}

VKP_FN uint envTexelOfUv(VKP_IN(EnvironmentInfo) info, vec2 uv) {
    uint x = min(uint(uv.x * float(info.width)), info.width - 1u);
    uint y = min(uint(uv.y * float(info.height)), info.height - 1u);
    return y * info.width + x;
}

// The four texels around map coordinates `uv` and the weights between them:
// the radiance there is envBilinearMix of the four texels' values.
struct EnvBilinear {
    uint texel00;  // column x0, row y0 (index y * width + x)
    uint texel10;  // x1, y0
    uint texel01;  // x0, y1
    uint texel11;  // x1, y1
    vec2 weight;   // the fractions of the way from x0 to x1 and from y0 to y1, in [0, 1)
};

VKP_FN EnvBilinear envBilinear(VKP_IN(EnvironmentInfo) info, vec2 uv) {
    // Continuous texel coordinates in which texel centres are integers.
    float x = uv.x * float(info.width) - 0.5f;
    float y = uv.y * float(info.height) - 0.5f;
    float fx = floor(x);
    float fy = floor(y);
    EnvBilinear b;
    b.weight = vec2(x - fx, y - fy);
    // u in [0, 1] gives fx in [-1, width - 1]: column -1 is the last one.
    uint x0 = uint(int(fx) + int(info.width)) % info.width;
    uint x1 = (x0 + 1u) % info.width;
    // v in [0, 1] gives fy in [-1, height - 1]: rows outside the map are the edge rows.
    int lastRow = int(info.height) - 1;
    uint y0 = uint(clamp(int(fy), 0, lastRow));
    uint y1 = uint(clamp(int(fy) + 1, 0, lastRow));
    b.texel00 = y0 * info.width + x0;
    b.texel10 = y0 * info.width + x1;
    b.texel01 = y1 * info.width + x0;
    b.texel11 = y1 * info.width + x1;
    return b;
}

// The radiance interpolated from the values of b's four texels.
VKP_FN vec3 envBilinearMix(EnvBilinear b, vec3 v00, vec3 v10, vec3 v01, vec3 v11) {
    return mix(mix(v00, v10, b.weight.x), mix(v01, v11, b.weight.x), b.weight.y);
}

// Solid-angle density of a map direction inside a cell of discrete
// probability `probability`: the cell is sampled uniformly in (u, v), and
// d omega = 2 pi^2 sin(theta) du dv. sin(theta) comes from the direction
// itself (length of its xz part), not from v through sin(), so that every
// path to the pdf of one direction computes the same number.
VKP_FN float envPdf(VKP_IN(EnvironmentInfo) info, float probability, vec3 mapDirection) {
    float sinTheta = length(vec2(mapDirection.x, mapDirection.z));
    if (!(sinTheta > 0.0f) || !(probability > 0.0f)) return 0.0f;
    float texelsPerUnitUv = float(info.width) * float(info.height);
    return probability * texelsPerUnitUv / (2.0f * VKP_PI * VKP_PI * sinTheta);
}

struct EnvSample {
    vec3 direction;  // world space
    vec2 uv;         // map coordinates
    uint pdfTexel;   // the cell whose probability gives the pdf: read it, then call envDirectionPdf
};

// A point uniformly inside the chosen texel's cell. Its pdf is evaluated from the
// direction (envDirectionPdf with the probability of s.pdfTexel), exactly as for
// a BSDF-sampled direction that escapes: the two MIS strategies then agree
// to the bit. The texel looked up from the direction is the chosen one except
// within ~1e-7 of a texel edge, where rounding of the mapping may pick the
// neighbour (measured by the tests).
VKP_FN EnvSample envSampleInTexel(VKP_IN(EnvironmentInfo) info, uint texel, vec2 jitter) {
    uint x = texel % info.width;
    uint y = texel / info.width;
    EnvSample s;
    s.uv =
        vec2((float(x) + jitter.x) / float(info.width), (float(y) + jitter.y) / float(info.height));
    // Keep the point inside the map: a jitter of 1 - 2^-24 can round up to
    // the texel's far edge, which for the last column or row is 1. (There the
    // point may fall in the neighbouring texel, which pdfTexel then names.)
    s.uv = min(s.uv, vec2(VKP_ONE_MINUS_EPSILON));
    vec3 mapDirection = equirectDirection(s.uv.x, s.uv.y);
    s.direction = envMapToWorld(info, mapDirection);
    s.pdfTexel = envTexelOfUv(info, equirectUv(mapDirection));
    return s;
}

// The pdf of a world direction, given the probability of its texel
// (the texel is envTexelOfUv(info, equirectUv(envWorldToMap(info, d)))).
VKP_FN float envDirectionPdf(VKP_IN(EnvironmentInfo) info, float texelProbability,
                             vec3 worldDirection) {
    return envPdf(info, texelProbability, envWorldToMap(info, worldDirection));
}

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::EnvironmentInfo) == 32);
#endif

#endif  // VKPATH_SHARED_ENVIRONMENT_SAMPLING_H
