// The path tracer's random numbers (shared/rng.h: rngUniform of either
// sampler) for a grid of (sample, dimension, pixel), for vkpath.sampler_values
// in Python.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "kernels/routines.h"
#include "shared/rng.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) writeonly buffer Values { float values[]; };
layout(push_constant, scalar) uniform Push { SamplerValuesPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    uint pixel = i % push.pixels;
    uint dimension = (i / push.pixels) % push.dimensions;
    uint sampleIndex = push.firstSample + i / (push.pixels * push.dimensions);
    values[i] = rngUniform(makeRngKey(pixel, sampleIndex, push.seed, push.samplerKind), dimension);
}
