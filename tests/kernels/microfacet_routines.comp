// Test kernel: samples one microfacet lobe of shaders/shared/microfacet.h per
// invocation with the RNG, and evaluates the lobe's f |cos| and pdf at the
// sampled direction, so the tests check the GPU's samples against the pdf
// (chi-square) and the GPU's weight against its own evaluation.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "kernels/microfacet_routines.h"
#include "shared/microfacet.h"
#include "shared/rng.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) writeonly buffer Results { MicrofacetResult results[]; };
layout(push_constant, scalar) uniform Push { MicrofacetPush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    RngKey key = makeRngKey(i, 0u, push.seed);
    vec2 u = rngUniform2(key, 0u);
    float uc = rngUniform(key, 2u);
    MicrofacetResult r;
    r.eval = vec3(0.0);
    r.evalPdf = 0.0;
    if (push.routine == MICROFACET_VISIBLE_NORMAL) {
        r.direction = sampleGgxVisibleNormal(push.wo, push.alpha, u);
        r.pdf = ggxVisibleNormalPdf(push.wo, r.direction, push.alpha);
        r.weight = vec3(1.0);
        r.flags = 1u;
        r.etaSquared = 1.0;
    } else {
        BsdfSample s;
        if (push.routine == MICROFACET_CONDUCTOR) {
            Conductor c;
            c.alpha = push.alpha;
            c.f0 = push.f0;
            c.eta = push.eta;
            c.k = push.k;
            c.fresnel = push.fresnel;
            c.multipleScattering = 0.0;
            s = sampleConductor(c, push.wo, u);
            if (s.valid) {
                r.eval = evalConductor(c, push.wo, s.direction);
                r.evalPdf = conductorPdf(c, push.wo, s.direction);
            }
        } else {
            RoughDielectric d;
            d.alpha = push.alpha;
            d.ior = push.ior;
            d.reflectance = vec3(1.0);
            d.transmittance = vec3(1.0);
            d.multipleScattering = 0.0;
            s = sampleRoughDielectric(d, push.wo, u, uc);
            if (s.valid) {
                r.eval = evalRoughDielectric(d, push.wo, s.direction);
                r.evalPdf = roughDielectricPdf(d, push.wo, s.direction);
            }
        }
        r.direction = s.direction;
        r.pdf = s.pdf;
        r.weight = s.weight;
        r.flags = (s.valid ? 1u : 0u) | (s.delta ? 2u : 0u);
        r.etaSquared = s.etaSquared;
    }
    results[i] = r;
}
