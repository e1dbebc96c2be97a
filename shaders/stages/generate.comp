// Stage "generate": starts the wave's paths (shared/integrator.h startPath).
// Path i of the wave is global path firstPath + i = sampleIndex * pixels +
// pixel; it enters ray queue 0.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "shared/path_state.h"
#include "stages/lib/path_buffers.glsl"
#include "stages/lib/queues.glsl"

layout(binding = VKP_WF_SCENE_INFO, scalar) readonly buffer SceneInfoBuffer { SceneInfo info; };
layout(binding = VKP_WF_CAMERA, scalar) readonly buffer CameraBuffer { Camera camera; };

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot == 0u) {
        setRayQueueSize(0u, push.pathCount);
        setRayQueueSize(1u, 0u);
        counters.shadowCount = 0u;
    }
    if (slot >= push.pathCount) return;
    uint path = push.firstPath + slot;
    uint pixels = camera.width * camera.height;
    uint pixel = path % pixels;
    PathState state = startPath(camera, pixel, pathRngKey(info, pixel, path / pixels));
    storePathVertex(slot, state);
    radiance[slot] = state.radiance;
    queues[rayQueueIndex(0u, slot)] = slot;
}
