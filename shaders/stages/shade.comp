// Stage "shade": at each hit of the current queue, adds what the ray sees
// (emission with its MIS weight, or the environment on a miss); then, unless
// the path has reached the maximum depth, queues its light samples' shadow
// rays and samples the BSDF for the next bounce. The math is the loop body of
// shared/integrator.h, cut where the shadow stage takes over.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/scene_access.glsl"
#include "stages/lib/path_buffers.glsl"
#include "stages/lib/queues.glsl"

layout(binding = VKP_WF_HITS, scalar) readonly buffer HitBuffer { Hit hits[]; };
layout(binding = VKP_WF_SHADOW_RAYS, scalar) writeonly buffer ShadowRayBuffer { Ray shadowRays[]; };
layout(binding = VKP_WF_SHADOW_RADIANCE, scalar) writeonly buffer ShadowRadianceBuffer { vec3 shadowRadiance[]; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    if (entry >= rayQueueSize(push.bounce)) return;
    uint slot = rayQueueSlot(push.bounce, entry);

    SceneInfo info = sceneInfo();
    uvec2 path = wavePath(slot, info.width * info.height);
    RngKey key = pathRngKey(info, path.x, path.y);
    PathState state = loadPath(slot);
    if (aovsWanted()) state.aov = pathAovs[slot];

    // ---- what the ray sees ------------------------------------------------------
    Shading shading;
    bool scatters = shadeHit(state, hits[slot], key, push.bounce, shading);
    radiance[slot] = state.radiance;
    if (aovsWanted()) pathAovs[slot] = state.aov;
    if (!scatters) return;

    // ---- next-event estimation ------------------------------------------------------
    bool queued = false;
    uint tracedShadowRays = 0u;  // the shadow stage traces the non-zero contributions
    uint rejectedLightSamples = 0u;
    for (uint j = 0u; j < lightSampleCount(); ++j) {
        ShadowRequest request = sampleDirectLight(shading, state.throughput, key, push.bounce, j);
        uint index = slot * lightSampleCount() + j;
        shadowRays[index] = request.ray;
        shadowRadiance[index] = request.valid ? request.contribution : vec3(0.0);
        queued = queued || request.valid;
        if (request.valid && request.contribution != vec3(0.0)) ++tracedShadowRays;
        if (request.rejected) ++rejectedLightSamples;
    }
    if (queued) pushShadowQueue(slot);
    if (tracedShadowRays > 0u) atomicAdd(counters.shadowRayCount, tracedShadowRays);
    if (rejectedLightSamples > 0u) atomicAdd(counters.rejectedLightSamples, rejectedLightSamples);

    // ---- the next bounce --------------------------------------------------------------
    if (!scatter(state, shading, key, push.bounce)) return;
    storePathVertex(slot, state);
    pushRayQueue(push.bounce + 1u, slot);
}
