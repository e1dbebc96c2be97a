// Stage "generate": starts the wave's paths. Path i of the wave is global
// path firstPath + i = sampleIndex * pixels + pixel; its camera ray is
// jittered inside the pixel (box filter), its throughput is 1, and it enters
// ray queue 0.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "shared/camera.h"
#include "shared/dimensions.h"
#include "shared/rng.h"
#include "shared/scene_data.h"

layout(binding = VKP_WF_SCENE_INFO, scalar) readonly buffer SceneInfoBuffer { SceneInfo info; };
layout(binding = VKP_WF_CAMERA, scalar) readonly buffer CameraBuffer { Camera camera; };
layout(binding = VKP_WF_RAYS, scalar) writeonly buffer RayBuffer { Ray rays[]; };
layout(binding = VKP_WF_THROUGHPUT, scalar) writeonly buffer ThroughputBuffer { vec3 throughput[]; };
layout(binding = VKP_WF_RADIANCE, scalar) writeonly buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_VERTEX, scalar) writeonly buffer VertexBuffer { PathVertex vertices[]; };
layout(binding = VKP_WF_QUEUES, scalar) writeonly buffer QueueBuffer { uint queues[]; };
layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot == 0u) {
        counters.rayCount0 = push.pathCount;
        counters.rayCount1 = 0u;
        counters.shadowCount = 0u;
    }
    if (slot >= push.pathCount) return;
    uint path = push.firstPath + slot;
    uint pixels = camera.width * camera.height;
    uint pixel = path % pixels;
    uint sampleIndex = path / pixels;
    uvec2 xy = uvec2(pixel % camera.width, pixel / camera.width);
    RngKey key = makeRngKey(pixel, sampleIndex, info.seed, info.samplerKind);
    rays[slot] = generateCameraRay(camera, xy, rngUniform2(key, VKP_DIM_PIXEL_JITTER));
    throughput[slot] = vec3(1.0);
    radiance[slot] = vec3(0.0);
    PathVertex v;
    v.position = camera.origin;
    v.bsdfPdf = 0.0;
    v.specular = 1u;
    vertices[slot] = v;
    queues[slot] = slot;
}
