// The megakernel: one invocation traces a whole path with shared/integrator.h
// tracePath (the loop the wavefront stages cut apart) and leaves its
// radiance for stage "accumulate". No per-path state but the radiance, no
// queues: the whole bounce loop stays in registers.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/scene_access.glsl"

layout(binding = VKP_WF_CAMERA, scalar) readonly buffer CameraBuffer { Camera camera; };
layout(binding = VKP_WF_RADIANCE, scalar) writeonly buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= push.pathCount) return;
    uint path = push.firstPath + slot;
    uint pixels = camera.width * camera.height;
    uint pixel = path % pixels;
    RngKey key = pathRngKey(sceneInfo(), pixel, path / pixels);
    PathTally tally;
    tally.closestRays = 0u;
    tally.shadowRays = 0u;
    tally.rejectedLightSamples = 0u;
    radiance[slot] = tracePath(startPath(camera, pixel, key), key, tally);
    atomicAdd(counters.closestRayCount, tally.closestRays);
    if (tally.shadowRays > 0u) atomicAdd(counters.shadowRayCount, tally.shadowRays);
    if (tally.rejectedLightSamples > 0u) atomicAdd(counters.rejectedLightSamples, tally.rejectedLightSamples);
}
