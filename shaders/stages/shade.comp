// Stage "shade": at each hit of the current queue, adds emission (with its
// MIS weight) or, on a miss, the environment; then, unless the path has
// reached the maximum depth, queues lightSamples shadow rays and samples the
// BSDF for the next bounce (shared/path_tracer.h has the math).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#include "stages/lib/common.glsl"
#include "stages/lib/scene_access.glsl"

layout(binding = VKP_WF_RAYS, scalar) buffer RayBuffer { Ray rays[]; };
layout(binding = VKP_WF_HITS, scalar) readonly buffer HitBuffer { Hit hits[]; };
layout(binding = VKP_WF_THROUGHPUT, scalar) buffer ThroughputBuffer { vec3 throughput[]; };
layout(binding = VKP_WF_RADIANCE, scalar) buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_VERTEX, scalar) buffer VertexBuffer { PathVertex vertices[]; };
layout(binding = VKP_WF_QUEUES, scalar) buffer QueueBuffer { uint queues[]; };
layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };
layout(binding = VKP_WF_SHADOW_RAYS, scalar) writeonly buffer ShadowRayBuffer { Ray shadowRays[]; };
layout(binding = VKP_WF_SHADOW_RADIANCE, scalar) writeonly buffer ShadowRadianceBuffer { vec3 shadowRadiance[]; };

void main() {
    uint entry = gl_GlobalInvocationID.x;
    bool odd = (push.bounce & 1u) == 1u;
    if (entry >= (odd ? counters.rayCount1 : counters.rayCount0)) return;
    uint slot = queues[(odd ? push.pathCount : 0u) + entry];

    SceneInfo info = sceneInfo();
    uint path = push.firstPath + slot;
    uint pixels = info.width * info.height;
    RngKey key = makeRngKey(path % pixels, path / pixels, info.seed, info.samplerKind);
    Ray ray = rays[slot];
    Hit hit = hits[slot];
    PathVertex previous = vertices[slot];
    vec3 beta = throughput[slot];
    bool specular = previous.specular != 0u;

    // ---- what the ray sees ------------------------------------------------------
    if (hit.primitive == VKP_NO_HIT) {
        radiance[slot] += beta * escapedRadiance(ray.direction, specular, previous.bsdfPdf);
        return;
    }
    BvhPrimitive primitive = bvhPrimitive(hit.primitive);
    Material material = sceneMaterial(primitive.material);
    SurfacePoint surface = surfacePoint(primitive, ray, hit);
    radiance[slot] += beta * emittedRadiance(material, hit.primitive, surface, ray.direction, previous.position,
                                             specular, previous.bsdfPdf);
    if (push.bounce >= info.maxDepth) return;

    // ---- next-event estimation ------------------------------------------------------
    vec3 wo = -ray.direction;
    bool anyShadow = false;
    uint tracedShadowRays = 0u;  // the shadow stage traces the non-zero contributions
    uint rejectedLightSamples = 0u;
    for (uint j = 0u; j < info.lightSamples; ++j) {
        ShadowRequest request = sampleDirectLight(material, surface, wo, beta, key, push.bounce, j);
        uint index = slot * info.lightSamples + j;
        shadowRays[index] = request.ray;
        shadowRadiance[index] = request.valid ? request.contribution : vec3(0.0);
        anyShadow = anyShadow || request.valid;
        if (request.valid && request.contribution != vec3(0.0)) ++tracedShadowRays;
        if (request.rejected) ++rejectedLightSamples;
    }
    if (anyShadow) queues[2u * push.pathCount + atomicAdd(counters.shadowCount, 1u)] = slot;
    if (tracedShadowRays > 0u) atomicAdd(counters.shadowRayCount, tracedShadowRays);
    if (rejectedLightSamples > 0u) atomicAdd(counters.rejectedLightSamples, rejectedLightSamples);

    // ---- the next bounce --------------------------------------------------------------
    PathStep step = continuePath(material, surface, wo, beta, key, push.bounce);
    if (!step.alive) return;
    rays[slot] = step.ray;
    throughput[slot] = step.throughput;
    PathVertex v;
    v.position = surface.position;
    v.bsdfPdf = step.bsdfPdf;
    v.specular = step.specular ? 1u : 0u;
    vertices[slot] = v;
    uint next = odd ? atomicAdd(counters.rayCount0, 1u) : push.pathCount + atomicAdd(counters.rayCount1, 1u);
    queues[next] = slot;
}
