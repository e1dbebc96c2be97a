// Stage "intersect": the closest hit of every ray in the current queue.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/scene_access.glsl"  // the BVH, and the materials and textures of the alpha test
#include "stages/lib/queues.glsl"

layout(binding = VKP_WF_RAYS, scalar) readonly buffer RayBuffer { Ray rays[]; };
layout(binding = VKP_WF_HITS, scalar) writeonly buffer HitBuffer { Hit hits[]; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    if (entry >= rayQueueSize(push.bounce)) return;
    uint slot = rayQueueSlot(push.bounce, entry);
    uint alphaKey = 0u;  // the ray's alpha decisions, keyed by its path (shared/alpha.h)
    SceneInfo info = sceneInfo();
    if (hasFeature(VKP_FEATURE_ALPHA) && info.alphaTested != 0u) {
        uvec2 path = wavePath(slot, info.width * info.height);
        alphaKey = alphaRayKey(pathRngKey(info, path.x, path.y), alphaClosestRay(push.bounce, lightSampleCount()));
    }
    hits[slot] = bvhClosestHit(rays[slot], alphaKey);
}
