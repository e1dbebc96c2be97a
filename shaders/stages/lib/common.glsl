// Declarations every stage kernel starts with (after #version and the
// include and scalar-layout extensions).

// Scenes beyond one binding are read by address (shared/bvh_buffers.h); the
// rest through texel buffers (samplerless texelFetch).
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#extension GL_EXT_samplerless_texture_functions : require

#include "stages/lib/float_controls.glsl"
#include "shared/bindings.h"
#include "shared/wavefront.h"

layout(local_size_x_id = VKP_SPEC_WORKGROUP_SIZE) in;

layout(push_constant, scalar) uniform Push { WavePush push; };

// An adaptive pass's pixels: (pixel, its first sample index) per entry.
layout(binding = VKP_WF_PIXEL_LIST, scalar) readonly buffer PixelListBuffer { uvec2 pixelList[]; };

// (pixel, sample index) of path slot `slot` of the wave: over the film's
// `pixels` in order, or over the pass's pixel list (shared/wavefront.h WavePush).
uvec2 wavePath(uint slot, uint pixels) {
    if (push.pixelListLength == 0u) return wavePathOf(push, slot, pixels);
    uvec2 entryRound = wavePathOf(push, slot, push.pixelListLength);
    uvec2 listed = pixelList[entryRound.x];
    return uvec2(listed.x, listed.y + entryRound.y);
}
