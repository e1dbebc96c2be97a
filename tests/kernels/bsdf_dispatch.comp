// Test kernel: samples the material in binding 1 through shared/bsdf.h's
// dispatch, one sample per invocation with the path tracer's random numbers
// (direction from dimensions 0-1, lobe choice from 2), and evaluates evalBsdf
// and bsdfPdf at the sampled direction, so the tests check the dispatch's
// samples against their density (chi-square) and its weights against its own
// f |cos| / pdf. The kernel is the general one (every feature bit set).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "kernels/bsdf_dispatch.h"
#include "kernels/microfacet_routines.h"
#include "shared/bsdf.h"
#include "shared/rng.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) writeonly buffer Results { MicrofacetResult results[]; };
layout(binding = 1, scalar) readonly buffer Materials { Material material; };
layout(push_constant, scalar) uniform Push { BsdfDispatchPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    RngKey key = makeRngKey(i, 0u, push.seed);
    BsdfSample s = sampleBsdf(material, push.ng, push.ns, push.wo, rngUniform2(key, 0u), rngUniform(key, 2u));
    MicrofacetResult r;
    r.direction = s.direction;
    r.pdf = s.pdf;
    r.weight = s.weight;
    r.flags = (s.valid ? 1u : 0u) | (s.delta ? 2u : 0u);
    r.etaSquared = s.etaSquared;
    r.eval = vec3(0.0);
    r.evalPdf = 0.0;
    if (s.valid) {
        r.eval = evalBsdf(material, push.ng, push.ns, push.wo, s.direction);
        r.evalPdf = bsdfPdf(material, push.ng, push.ns, push.wo, s.direction);
    }
    results[i] = r;
}
