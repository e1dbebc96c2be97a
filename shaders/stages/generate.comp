// Stage "generate": starts the wave's paths (shared/integrator.h startPath).
// Path slot i of the wave is wavePath(i) (stages/lib/common.glsl); it
// enters ray queue 0.
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
    uvec2 path = wavePath(slot, camera.width * camera.height);
    PathState state = startPath(camera, path.x, pathRngKey(info, path.x, path.y));
    storePathVertex(slot, state);
    radiance[slot] = state.radiance;
    if (hasFeature(VKP_FEATURE_AOVS) && info.aovs != 0u) pathAovs[slot] = state.aov;
    queues[rayQueueIndex(0u, slot)] = slot;
}
