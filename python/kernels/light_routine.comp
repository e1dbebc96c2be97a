// The light sampling of next-event estimation and the environment's density
// and radiance over an array of inputs, for vkpath.Scene.sample_lights and
// environment in Python: the general kernel over the scene's arrays, bound as
// the stage kernels bind them (stages/lib/scene_access.glsl).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#extension GL_EXT_samplerless_texture_functions : require

#include "stages/lib/float_controls.glsl"
#include "shared/bindings.h"
#include "shared/wavefront.h"
#include "kernels/routines.h"

layout(local_size_x_id = VKP_SPEC_WORKGROUP_SIZE) in;

#include "stages/lib/scene_access.glsl"

layout(binding = VKP_ROUTINE_INPUTS, scalar) readonly buffer Inputs { LightRoutineInput inputs[]; };
layout(binding = VKP_ROUTINE_OUTPUTS, scalar) writeonly buffer Outputs { LightRoutineOutput outputs[]; };
layout(push_constant, scalar) uniform Push { LightRoutinePush push; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    LightRoutineInput a = inputs[i];
    RngKey key = makeRngKey(i, push.sampleIndex, push.seed, push.samplerKind);
    SceneLightSample chosen = sampleSceneLight(a.point, vec3(0.0f), key, 0u);  // no surface
    LightRoutineOutput r;
    r.direction = chosen.lightSample.direction;
    r.distance = chosen.lightSample.distance;
    r.radiance = chosen.lightSample.radiance;
    r.pdf = chosen.lightSample.pdf;
    r.normal = chosen.lightSample.normal;
    r.choice = chosen.choice;
    r.lightIndex = chosen.lightIndex;
    r.delta = chosen.lightSample.delta ? 1u : 0u;
    r.environmentRadiance = environmentRadiance(a.direction);
    r.environmentPdf = environmentPdf(a.direction);
    outputs[i] = r;
}
