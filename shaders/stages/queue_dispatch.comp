// Stage "queue_dispatch": one thread turns a queue's count into the
// indirect-dispatch arguments of the stages that consume it, so the host
// never reads counts back between bounces.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"

// The workgroup size of the consuming stages.
layout(constant_id = 1) const uint CONSUMER_WORKGROUP_SIZE = 64u;

layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };

// total += n for a 64-bit (low, high) pair.
uvec2 add64(uvec2 total, uint n) {
    uint carry;
    uint low = uaddCarry(total.x, n, carry);
    return uvec2(low, total.y + carry);
}

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    if (push.mode == VKP_PREPARE_RAYS) {
        bool odd = (push.bounce & 1u) == 1u;
        uint count = odd ? counters.rayCount1 : counters.rayCount0;
        counters.rayDispatch = uvec3((count + CONSUMER_WORKGROUP_SIZE - 1u) / CONSUMER_WORKGROUP_SIZE, 1u, 1u);
        counters.closestRays = add64(counters.closestRays, count);
        if (odd)
            counters.rayCount0 = 0u;
        else
            counters.rayCount1 = 0u;
        counters.shadowCount = 0u;
    } else {
        uint count = counters.shadowCount;
        counters.shadowDispatch = uvec3((count + CONSUMER_WORKGROUP_SIZE - 1u) / CONSUMER_WORKGROUP_SIZE, 1u, 1u);
        counters.shadowRays = add64(counters.shadowRays, counters.shadowRayCount);
        counters.shadowRayCount = 0u;
    }
}
