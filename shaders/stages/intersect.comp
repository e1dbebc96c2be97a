// Stage "intersect": the closest hit of every ray in the current queue.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "shared/ray.h"

#include "stages/lib/scene_bvh.glsl"
#include "stages/lib/queues.glsl"

layout(binding = VKP_WF_RAYS, scalar) readonly buffer RayBuffer { Ray rays[]; };
layout(binding = VKP_WF_HITS, scalar) writeonly buffer HitBuffer { Hit hits[]; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    if (entry >= rayQueueSize(push.bounce)) return;
    uint slot = rayQueueSlot(push.bounce, entry);
    hits[slot] = bvhClosestHit(rays[slot]);
}
