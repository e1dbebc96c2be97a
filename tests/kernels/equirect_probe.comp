// Test kernel: the equirectangular mapping (shared/environment_map.h) run on
// the GPU, so the environment test can compare it with the same functions
// compiled as C++.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "shared/environment_map.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) readonly buffer Uvs { vec2 uvs[]; };
layout(binding = 1, scalar) writeonly buffer Directions { vec3 directions[]; };
layout(binding = 2, scalar) writeonly buffer RoundTrips { vec2 roundTrips[]; };
layout(push_constant, scalar) uniform Push { uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    vec3 direction = equirectDirection(uvs[i].x, uvs[i].y);
    directions[i] = direction;
    roundTrips[i] = equirectUv(direction);
}
