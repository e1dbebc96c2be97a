// Test kernel: runs one sampling routine of shaders/shared/ per invocation
// with the RNG, so the tests check the GPU's samples against the routine's
// own pdf (chi-square) and the discrete choices against their probabilities.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "kernels/sampling_routines.h"
#include "shared/bsdf.h"
#include "shared/phase.h"
#include "shared/rng.h"
#include "shared/sampling.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) writeonly buffer Results { SamplingResult results[]; };
layout(push_constant, scalar) uniform Push { SamplingPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    RngKey key = makeRngKey(i, 0u, push.seed);
    vec2 u = rngUniform2(key, 0u);
    SamplingResult r;
    r.direction = vec3(0.0);
    r.pdf = 0.0;
    r.weight = vec3(1.0);
    r.flags = 1u;
    if (push.routine == ROUTINE_COSINE_HEMISPHERE) {
        r.direction = sampleCosineHemisphere(u);
        r.pdf = cosineHemispherePdf(r.direction.z);
    } else if (push.routine == ROUTINE_UNIFORM_SPHERE) {
        r.direction = sampleUniformSphere(u);
        r.pdf = uniformSpherePdf();
    } else if (push.routine == ROUTINE_UNIFORM_HEMISPHERE) {
        r.direction = sampleUniformHemisphere(u);
        r.pdf = uniformHemispherePdf();
    } else if (push.routine == ROUTINE_SPHERE_CONE) {
        SphereCone cone = sphereCone(push.b, push.scalar, push.a);
        r.direction = sampleSphereCone(cone, normalize(push.b - push.a), u);
        r.pdf = sphereConePdf(cone);
    } else if (push.routine == ROUTINE_HENYEY_GREENSTEIN) {
        r.direction = sampleHenyeyGreenstein(push.b, push.scalar, u);
        r.pdf = henyeyGreenstein(dot(push.b, r.direction), push.scalar);
    } else if (push.routine == ROUTINE_TRIANGLE_AREA) {
        r.direction = vec3(sampleTriangleBarycentrics(u), 0.0);
        r.pdf = 1.0 / length(triangleArea3(push.a, push.b, push.c));
    } else {
        BsdfSample s;
        if (push.routine == ROUTINE_LAMBERTIAN)
            s = sampleLambertian(vec3(1.0), push.a, push.b, u);
        else if (push.routine == ROUTINE_DIELECTRIC)
            s = sampleDielectric(vec3(1.0), vec3(1.0), push.scalar, push.a, push.b, u.x);
        else
            s = sampleMirror(vec3(1.0), push.a, push.b);
        r.direction = s.direction;
        r.pdf = s.pdf;
        r.weight = s.weight;
        r.flags = (s.valid ? 1u : 0u) | (s.delta ? 2u : 0u);
    }
    results[i] = r;
}
