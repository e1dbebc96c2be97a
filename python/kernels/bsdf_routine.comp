// shared/bsdf.h's dispatch (sampleBsdf, evalBsdf, bsdfPdf) over an array of
// inputs, for vkpath.bsdf in Python: the general kernel (every feature bit
// set), so every material kind runs through the path tracer's own code.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "kernels/routines.h"
#include "shared/bsdf.h"

layout(local_size_x_id = 0) in;

layout(binding = 0, scalar) readonly buffer Inputs { BsdfRoutineInput inputs[]; };
layout(binding = 1, scalar) writeonly buffer Outputs { BsdfRoutineOutput outputs[]; };
layout(binding = 2, scalar) readonly buffer Materials { Material material; };
layout(push_constant, scalar) uniform Push { BsdfRoutinePush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    const vec3 n = vec3(0.0, 0.0, 1.0);
    BsdfRoutineInput a = inputs[i];
    BsdfSample s = sampleBsdf(material, n, n, a.wo, a.u.xy, a.u.z);
    BsdfRoutineOutput r;
    r.direction = s.direction;
    r.pdf = s.pdf;
    r.weight = s.weight;
    r.flags = (s.valid ? 1u : 0u) | (s.delta ? 2u : 0u);
    r.etaSquared = s.etaSquared;
    vec3 wi = push.atSample != 0u ? s.direction : a.wi;
    bool evaluated = push.atSample == 0u || s.valid;
    r.eval = evaluated ? evalBsdf(material, n, n, a.wo, wi) : vec3(0.0);
    r.evalPdf = evaluated ? bsdfPdf(material, n, n, a.wo, wi) : 0.0;
    outputs[i] = r;
}
