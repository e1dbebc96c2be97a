// Declares a runtime array of every struct in shaders/shared/, so the layout
// test can read each one's member offsets and array stride from the SPIR-V
// and compare them with the C++ compiler's offsetof and sizeof.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "shared/bindings.h"
#include "shared/camera.h"
#include "shared/material.h"
#include "shared/ray.h"

layout(local_size_x = 1) in;

layout(binding = 0, scalar) buffer Rays { Ray rays[]; };
layout(binding = 1, scalar) buffer Cameras { Camera cameras[]; };
layout(binding = 2, scalar) buffer GeneratePushes { GeneratePush generatePushes[]; };
layout(binding = 3, scalar) buffer Materials { Material materials[]; };

void main() {
    // Touch every array so the compiler keeps the declarations.
    rays[0] = rays[1];
    cameras[0] = cameras[1];
    generatePushes[0] = generatePushes[1];
    materials[0] = materials[1];
}
