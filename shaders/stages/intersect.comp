// Stage "intersect": the closest hit of every ray in the current queue.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "shared/ray.h"

#include "stages/lib/scene_bvh.glsl"

layout(binding = VKP_WF_RAYS, scalar) readonly buffer RayBuffer { Ray rays[]; };
layout(binding = VKP_WF_HITS, scalar) writeonly buffer HitBuffer { Hit hits[]; };
layout(binding = VKP_WF_QUEUES, scalar) readonly buffer QueueBuffer { uint queues[]; };
layout(binding = VKP_WF_COUNTERS, scalar) readonly buffer CounterBuffer { QueueCounters counters; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    bool odd = (push.bounce & 1u) == 1u;
    if (entry >= (odd ? counters.rayCount1 : counters.rayCount0)) return;
    uint slot = queues[(odd ? push.pathCount : 0u) + entry];
    hits[slot] = bvhClosestHit(rays[slot]);
}
