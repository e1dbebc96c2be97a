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
