// Stage "shadow": each queued path's shadow rays; an unoccluded one adds its
// contribution to the path's radiance. One thread per path (not per ray), so
// the additions to a path happen in a fixed order: renders are deterministic.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "shared/ray.h"
#include "shared/scene_data.h"

#include "stages/lib/scene_bvh.glsl"

layout(binding = VKP_WF_SCENE_INFO, scalar) readonly buffer SceneInfoBuffer { SceneInfo info; };
layout(binding = VKP_WF_RADIANCE, scalar) buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_QUEUES, scalar) readonly buffer QueueBuffer { uint queues[]; };
layout(binding = VKP_WF_COUNTERS, scalar) readonly buffer CounterBuffer { QueueCounters counters; };
layout(binding = VKP_WF_SHADOW_RAYS, scalar) readonly buffer ShadowRayBuffer { Ray shadowRays[]; };
layout(binding = VKP_WF_SHADOW_RADIANCE, scalar) readonly buffer ShadowRadianceBuffer { vec3 shadowRadiance[]; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    if (entry >= counters.shadowCount) return;
    uint slot = queues[2u * push.pathCount + entry];
    vec3 sum = vec3(0.0);
    for (uint j = 0u; j < info.lightSamples; ++j) {
        uint index = slot * info.lightSamples + j;
        vec3 contribution = shadowRadiance[index];
        if (contribution == vec3(0.0)) continue;
        if (!bvhOccluded(shadowRays[index])) sum += contribution;
    }
    radiance[slot] += sum;
}
