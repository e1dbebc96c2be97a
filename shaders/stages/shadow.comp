// Stage "shadow": each queued path's shadow rays; an unoccluded one adds its
// contribution to the path's radiance. One thread per path (not per ray), so
// the additions to a path happen in a fixed order, the order of
// shared/integrator.h's loop: renders are deterministic.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/scene_access.glsl"  // the BVH, and the materials and textures of the alpha test
#include "stages/lib/queues.glsl"

layout(binding = VKP_WF_RADIANCE, scalar) buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_SHADOW_RAYS, scalar) readonly buffer ShadowRayBuffer { Ray shadowRays[]; };
layout(binding = VKP_WF_SHADOW_RADIANCE, scalar) readonly buffer ShadowRadianceBuffer { vec3 shadowRadiance[]; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    if (entry >= shadowQueueSize()) return;
    uint slot = shadowQueueSlot(entry);
    SceneInfo info = sceneInfo();
    RngKey key = makeRngKey(0u, 0u, 0u);  // the path's: its rays' alpha decisions (shared/alpha.h)
    if (hasFeature(VKP_FEATURE_ALPHA) && info.alphaTested != 0u) {
        uvec2 path = wavePath(slot, info.width * info.height);
        key = pathRngKey(info, path.x, path.y);
    }
    vec3 unoccluded = vec3(0.0);
    uint samples = featureLightSamples(info.lightSamples);
    for (uint j = 0u; j < samples; ++j) {
        uint index = slot * samples + j;
        vec3 contribution = shadowRadiance[index];
        if (contribution == vec3(0.0)) continue;
        uint alphaKey = pathAlphaKey(key, alphaShadowRay(push.bounce, samples, j));
        if (!bvhOccluded(shadowRays[index], alphaKey)) unoccluded += contribution;
    }
    radiance[slot] += unoccluded;
}
