// The megakernel: each invocation traces whole paths with shared/integrator.h
// (the loop the wavefront stages cut apart), one bounce per iteration, and
// leaves each path's radiance for stage "accumulate". Path regeneration
// (Novak, Havran and Dachsbacher 2010, "Path Regeneration for Interactive
// Path Tracing"): an invocation whose path has ended starts its next one in
// the same iteration, so the SIMD lanes of a group keep tracing instead of
// idling until the group's longest path is done. Invocation i takes the
// wave's paths i, i + N, i + 2N, ... (N invocations in the dispatch). No
// per-path state but the radiance (and the AOVs when asked), no queues: the
// loop stays in registers.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/scene_access.glsl"

layout(binding = VKP_WF_CAMERA, scalar) readonly buffer CameraBuffer { Camera camera; };
layout(binding = VKP_WF_RADIANCE, scalar) writeonly buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_PATH_AOV, scalar) writeonly buffer PathAovBuffer { PathAov pathAovs[]; };
layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };

uint pixels() { return camera.width * camera.height; }

RngKey keyOf(uint slot) {
    uvec2 path = wavePath(slot, pixels());
    return pathRngKey(sceneInfo(), path.x, path.y);
}

void main() {
    uint slot = gl_GlobalInvocationID.x;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    if (slot >= push.pathCount) return;
    PathTally tally;
    tally.closestRays = 0u;
    tally.shadowRays = 0u;
    tally.rejectedLightSamples = 0u;
    RngKey key = keyOf(slot);
    PathState state = startPath(camera, key.pixel, key);
    uint bounce = 0u;
    for (;;) {
        if (traceBounce(state, key, bounce, tally)) {
            ++bounce;
            continue;
        }
        radiance[slot] = state.radiance;
        if (aovsWanted()) pathAovs[slot] = state.aov;
        slot += stride;
        if (slot >= push.pathCount) break;
        key = keyOf(slot);
        state = startPath(camera, key.pixel, key);
        bounce = 0u;
    }
    atomicAdd(counters.closestRayCount, tally.closestRays);
    if (tally.shadowRays > 0u) atomicAdd(counters.shadowRayCount, tally.shadowRays);
    if (tally.rejectedLightSamples > 0u) atomicAdd(counters.rejectedLightSamples, tally.rejectedLightSamples);
}
