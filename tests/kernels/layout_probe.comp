// Declares a runtime array of every struct in shaders/shared/, so the layout
// test can read each one's member offsets and array stride from the SPIR-V
// and compare them with the C++ compiler's offsetof and sizeof.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "shared/alias.h"
#include "shared/alpha.h"
#include "shared/bvh.h"
#include "shared/camera.h"
#include "shared/light_tree.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/mesh_attributes.h"
#include "shared/path_state.h"
#include "shared/ray.h"
#include "shared/scene_addresses.h"
#include "shared/scene_data.h"
#include "shared/texture.h"
#include "shared/wavefront.h"

layout(local_size_x = 1) in;

#define PROBE(T, b) layout(binding = b, scalar) buffer T##Array { T items##b[]; };
PROBE(Ray, 0)
PROBE(Camera, 1)
PROBE(Material, 2)
PROBE(BvhNode, 3)
PROBE(BvhPrimitive, 4)
PROBE(Hit, 5)
PROBE(TracePush, 6)
PROBE(AliasEntry, 7)
PROBE(EnvironmentInfo, 8)
PROBE(SceneInfo, 9)
PROBE(Light, 10)
PROBE(PathVertex, 11)
PROBE(QueueCounters, 12)
PROBE(FilmPixel, 13)
PROBE(WavePush, 14)
PROBE(BvhAddresses, 15)
PROBE(SceneAddresses, 16)
PROBE(TriangleVertices, 17)
PROBE(TextureInfo, 18)
PROBE(TextureSlot, 19)
PROBE(MaterialAlpha, 20)
PROBE(PathAov, 21)
PROBE(FilmAovPixel, 22)
PROBE(RayQueryGeometry, 23)
PROBE(LightTreeNode, 24)

void main() {
    // Touch every array so the compiler keeps the declarations.
    items0[0] = items0[1];
    items1[0] = items1[1];
    items2[0] = items2[1];
    items3[0] = items3[1];
    items4[0] = items4[1];
    items5[0] = items5[1];
    items6[0] = items6[1];
    items7[0] = items7[1];
    items8[0] = items8[1];
    items9[0] = items9[1];
    items10[0] = items10[1];
    items11[0] = items11[1];
    items12[0] = items12[1];
    items13[0] = items13[1];
    items14[0] = items14[1];
    items15[0] = items15[1];
    items16[0] = items16[1];
    items17[0] = items17[1];
    items18[0] = items18[1];
    items19[0] = items19[1];
    items20[0] = items20[1];
    items21[0] = items21[1];
    items22[0] = items22[1];
    items23[0] = items23[1];
    items24[0] = items24[1];
}
