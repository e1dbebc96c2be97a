// Stage "accumulate": adds each path's radiance to its pixel with
// compensated (Kahan) sums, one thread per pixel of the film window bound
// (shared/wavefront.h WavePush.filmFirstPixel) looping over the wave's
// samples of that pixel in order (deterministic). A sample whose radiance is
// NaN or infinite, or that would overflow the sums, is dropped and counted,
// never added. Samples above the
// firefly threshold are counted; with --clamp they are scaled down to it
// (keeping their colour), which is biased and therefore off by default.
// With the AOVs (SceneInfo::aovs) each path's albedo and normal are added to
// the pixel's AOV sums too, dropped samples included (their AOVs are finite).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "shared/path_state.h"
#include "shared/scene_data.h"

layout(binding = VKP_WF_SCENE_INFO, scalar) readonly buffer SceneInfoBuffer { SceneInfo info; };
layout(binding = VKP_WF_RADIANCE, scalar) readonly buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };
layout(binding = VKP_WF_FILM, scalar) buffer FilmBuffer { FilmPixel film[]; };
// The window's odd-stream sums (two sample streams), parallel to the film's.
layout(binding = VKP_WF_FILM_ODD, scalar) buffer FilmOddBuffer { FilmStreamPixel filmOdd[]; };
// The AOVs: each path's, and the window's sums, parallel to the film's.
layout(binding = VKP_WF_PATH_AOV, scalar) readonly buffer PathAovBuffer { PathAov pathAovs[]; };
layout(binding = VKP_WF_FILM_AOV, scalar) buffer FilmAovBuffer { FilmAovPixel filmAov[]; };

// By bit pattern: a compiler may fold isnan()/isinf() away under fast-math
// assumptions; exponent all ones means NaN or infinity.
bool finiteBits(vec3 v) {
    uvec3 bits = floatBitsToUint(v) & 0x7f800000u;
    return all(notEqual(bits, uvec3(0x7f800000u)));
}

// Kahan summation; `precise` forbids the reassociation that would cancel
// the compensation to zero.
void kahanAdd(inout vec3 sum, inout vec3 compensation, vec3 value) {
    precise vec3 y = value - compensation;
    precise vec3 t = sum + y;
    precise vec3 c = (t - sum) - y;
    compensation = c;
    sum = t;
}

// Adds the wave's paths at linear positions first, first + stride, ...
// (below the wave's end) to film[slot], in order; with two sample streams
// the odd-indexed ones also to filmOdd[slot]. The path at `first` has sample
// index firstIndex, and each next one the index after.
void accumulatePixel(uint slot, uint first, uint stride, uint firstIndex) {
    uint end = push.firstPixel + push.pathCount;
    if (first >= end) return;
    bool streams = info.sampleStreams == 2u;
    FilmStreamPixel odd;
    if (streams) odd = filmOdd[slot];
    bool aovs = info.aovs != 0u;
    FilmAovPixel aov;
    if (aovs) aov = filmAov[slot];
    uint index = firstIndex;
    FilmPixel f = film[slot];
    uint dropped = 0u;
    uint fireflies = 0u;
    for (uint linear = first; linear < end; linear += stride, ++index) {
        vec3 l = radiance[linear - push.firstPixel];
        if (aovs) {
            PathAov a = pathAovs[linear - push.firstPixel];
            aov.albedo += a.albedo;
            aov.normal += a.normal;
            aov.samples += 1u;
        }
        if (!finiteBits(l)) {
            dropped++;
            continue;
        }
        float largest = max(max(l.x, l.y), l.z);
        if (largest > info.fireflyThreshold) fireflies++;
        if (info.clampRadiance > 0.0 && largest > info.clampRadiance) l *= info.clampRadiance / largest;
        // A finite sample can still overflow the sums (a 1e38 emitter seen
        // directly): such a sample is rejected like a NaN, so no pixel
        // becomes infinite.
        FilmPixel next = f;
        kahanAdd(next.sum, next.sumCompensation, l);
        kahanAdd(next.sumSquares, next.sumSquaresCompensation, l * l);
        if (!finiteBits(next.sum) || !finiteBits(next.sumSquares) || !finiteBits(next.sumCompensation) ||
            !finiteBits(next.sumSquaresCompensation)) {
            dropped++;
            continue;
        }
        f = next;
        if (streams && (index & 1u) == 1u) kahanAdd(odd.sum, odd.sumCompensation, l);
    }
    film[slot] = f;
    if (streams) filmOdd[slot] = odd;
    if (aovs) filmAov[slot] = aov;
    if (dropped > 0u) atomicAdd(counters.nonFinite, dropped);
    if (fireflies > 0u) atomicAdd(counters.fireflies, fireflies);
}

void main() {
    // The film buffer bound is the window of pixels from push.filmFirstPixel.
    if (push.pixelListLength > 0u) {
        // An adaptive pass: one thread per list entry in the window, from
        // push.listFirstEntry (the list is ascending, so the window's entries
        // are consecutive); its paths are the linear positions congruent to
        // the entry modulo the list's length.
        uint entry = push.listFirstEntry + gl_GlobalInvocationID.x;
        if (entry >= push.pixelListLength) return;
        uint slot = pixelList[entry].x - push.filmFirstPixel;  // wraps below the window
        if (slot >= film.length()) return;
        uint length = push.pixelListLength;
        uint first = push.firstPixel + (entry + length - push.firstPixel % length) % length;
        accumulatePixel(slot, first, length, pixelList[entry].y + push.firstSample + first / length);
        return;
    }
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= film.length()) return;
    uint pixel = push.filmFirstPixel + slot;
    uint pixels = info.width * info.height;
    if (pixel >= pixels) return;
    // The wave holds the paths of linear positions [firstPixel, firstPixel +
    // pathCount) from its first sample (shared/wavefront.h wavePathOf); this
    // pixel's are those congruent to it modulo the pixel count.
    uint first = push.firstPixel + (pixel + pixels - push.firstPixel) % pixels;
    accumulatePixel(slot, first, pixels, push.firstSample + first / pixels);
}
