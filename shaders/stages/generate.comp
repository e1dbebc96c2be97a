// Stage "generate": one camera ray per pixel for one sample index, jittered
// inside the pixel by the RNG (box filter).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "shared/bindings.h"
#include "shared/camera.h"
#include "shared/dimensions.h"
#include "shared/rng.h"

layout(local_size_x_id = VKP_SPEC_WORKGROUP_SIZE) in;

layout(binding = VKP_GENERATE_BINDING_CAMERA, scalar) readonly buffer CameraBuffer {
    Camera camera;
};
layout(binding = VKP_GENERATE_BINDING_RAYS, scalar) writeonly buffer RayBuffer {
    Ray rays[];
};
layout(push_constant, scalar) uniform Push {
    GeneratePush push;
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    uint pixel = push.firstPixel + i;
    uvec2 xy = uvec2(pixel % camera.width, pixel / camera.width);
    RngKey key = makeRngKey(pixel, push.sampleIndex, push.seed);
    rays[i] = generateCameraRay(camera, xy, rngUniform2(key, VKP_DIM_PIXEL_JITTER));
}
