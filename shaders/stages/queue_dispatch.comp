// Stage "queue_dispatch": one thread turns a queue's size into the
// indirect-dispatch arguments of the stages that consume it, so the host
// never reads counts back between bounces; it also adds the rays a stage
// traced to the render's 64-bit totals.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/queues.glsl"

// The workgroup size of the consuming stages.
layout(constant_id = 1) const uint CONSUMER_WORKGROUP_SIZE = 64u;

// total += n for a 64-bit (low, high) pair.
uvec2 add64(uvec2 total, uint n) {
    uint carry;
    uint low = uaddCarry(total.x, n, carry);
    return uvec2(low, total.y + carry);
}

uvec3 groupsFor(uint count) { return uvec3((count + CONSUMER_WORKGROUP_SIZE - 1u) / CONSUMER_WORKGROUP_SIZE, 1u, 1u); }

void main() {
    if (gl_GlobalInvocationID.x != 0u) return;
    if (push.mode == VKP_PREPARE_RAYS) {
        uint count = rayQueueSize(push.bounce);
        counters.rayDispatch = groupsFor(count);
        counters.closestRays = add64(counters.closestRays, count);
        setRayQueueSize(push.bounce + 1u, 0u);
        counters.shadowCount = 0u;
    } else if (push.mode == VKP_PREPARE_SHADOWS) {
        counters.shadowDispatch = groupsFor(shadowQueueSize());
        counters.shadowRays = add64(counters.shadowRays, counters.shadowRayCount);
        counters.shadowRayCount = 0u;
    } else {  // VKP_TALLY_RAYS: the megakernel's counts of one wave
        counters.closestRays = add64(counters.closestRays, counters.closestRayCount);
        counters.shadowRays = add64(counters.shadowRays, counters.shadowRayCount);
        counters.closestRayCount = 0u;
        counters.shadowRayCount = 0u;
    }
}
