// Every struct in shaders/shared/ must have the same layout in GLSL (scalar
// block layout, read from the SPIR-V of tests/kernels/layout_probe.comp) and
// in C++ (offsetof, sizeof). Nothing else would notice a mismatch.
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

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
#include "vk/embedded_shaders.h"
#include "vk/spirv_reflect.h"

namespace {

using namespace vkpath;
using namespace vkpath::shared;

struct Expected {
    const char* name;
    size_t size;
    std::vector<uint32_t> offsets;
};

#define VKP_OFFSET(T, m) static_cast<uint32_t>(offsetof(T, m))

#define VKP_O(T, m) VKP_OFFSET(T, m)

std::vector<Expected> expectedLayouts() {
    return {
        {"Ray",
         sizeof(Ray),
         {VKP_O(Ray, origin), VKP_O(Ray, tMax), VKP_O(Ray, direction), VKP_O(Ray, pixel)}},
        {"Camera",
         sizeof(Camera),
         {VKP_O(Camera, origin), VKP_O(Camera, forward), VKP_O(Camera, right), VKP_O(Camera, up),
          VKP_O(Camera, width), VKP_O(Camera, height)}},
        {"Material",
         sizeof(Material),
         {VKP_O(Material, reflectance),
          VKP_O(Material, kind),
          VKP_O(Material, transmittance),
          VKP_O(Material, ior),
          VKP_O(Material, emission),
          VKP_O(Material, textures),
          VKP_O(Material, roughness),
          VKP_O(Material, metallic),
          VKP_O(Material, specular),
          VKP_O(Material, flags),
          VKP_O(Material, attenuation),
          VKP_O(Material, multipleScattering),
          VKP_O(Material, sheenColor),
          VKP_O(Material, sheenRoughness),
          VKP_O(Material, clearcoat),
          VKP_O(Material, clearcoatRoughness),
          VKP_O(Material, sheenLobeAlbedo),
          VKP_O(Material, dispersion),
          VKP_O(Material, diffuseTransmissionColor),
          VKP_O(Material, diffuseTransmission),
          VKP_O(Material, iridescence),
          VKP_O(Material, iridescenceIor),
          VKP_O(Material, iridescenceThicknessMinimum),
          VKP_O(Material, iridescenceThickness),
          VKP_O(Material, anisotropyDirection),
          VKP_O(Material, anisotropy),
          VKP_O(Material, clearcoatNormal),
          VKP_O(Material, padding)}},
        {"TextureInfo",
         sizeof(TextureInfo),
         {VKP_O(TextureInfo, firstTexel), VKP_O(TextureInfo, width), VKP_O(TextureInfo, height),
          VKP_O(TextureInfo, sampling)}},
        {"TextureSlot",
         sizeof(TextureSlot),
         {VKP_O(TextureSlot, transformU), VKP_O(TextureSlot, texture),
          VKP_O(TextureSlot, transformV), VKP_O(TextureSlot, texCoord), VKP_O(TextureSlot, scale),
          VKP_O(TextureSlot, padding)}},
        {"BvhNode",
         sizeof(BvhNode),
         {VKP_O(BvhNode, boundsMin), VKP_O(BvhNode, offset), VKP_O(BvhNode, boundsMax),
          VKP_O(BvhNode, count)}},
        {"BvhPrimitive",
         sizeof(BvhPrimitive),
         {VKP_O(BvhPrimitive, p0), VKP_O(BvhPrimitive, kind), VKP_O(BvhPrimitive, p1),
          VKP_O(BvhPrimitive, id), VKP_O(BvhPrimitive, p2), VKP_O(BvhPrimitive, material)}},
        {"Hit",
         sizeof(Hit),
         {VKP_O(Hit, t), VKP_O(Hit, primitive), VKP_O(Hit, barycentrics), VKP_O(Hit, instance)}},
        {"TracePush", sizeof(TracePush), {VKP_O(TracePush, count), VKP_O(TracePush, bvh)}},
        {"BvhAddresses",
         sizeof(BvhAddresses),
         {VKP_O(BvhAddresses, nodes), VKP_O(BvhAddresses, primitives),
          VKP_O(BvhAddresses, accelerationStructure), VKP_O(BvhAddresses, rayQueryGeometries),
          VKP_O(BvhAddresses, rayQueryIndices)}},
        {"RayQueryGeometry",
         sizeof(RayQueryGeometry),
         {VKP_O(RayQueryGeometry, firstIndex), VKP_O(RayQueryGeometry, stride),
          VKP_O(RayQueryGeometry, instance), VKP_O(RayQueryGeometry, padding)}},
        {"LightTreeNode",
         sizeof(LightTreeNode),
         {VKP_O(LightTreeNode, boundsMin), VKP_O(LightTreeNode, power),
          VKP_O(LightTreeNode, boundsMax), VKP_O(LightTreeNode, index), VKP_O(LightTreeNode, axis),
          VKP_O(LightTreeNode, cosNormals), VKP_O(LightTreeNode, cosEmission),
          VKP_O(LightTreeNode, flags), VKP_O(LightTreeNode, frontPlane),
          VKP_O(LightTreeNode, padding)}},
        {"SceneAddresses",
         sizeof(SceneAddresses),
         {VKP_O(SceneAddresses, bvh)
#define VKP_ADDRESS_OFFSET(index, name, Record, access, member) \
    VKP_SCENE_ARRAY_IF_SPANS_##access(VKP_ADDRESS_OFFSET_OF(name))
#define VKP_ADDRESS_OFFSET_OF(name) , VKP_O(SceneAddresses, name)
              VKP_SCENE_ARRAYS(VKP_ADDRESS_OFFSET)
#undef VKP_ADDRESS_OFFSET_OF
#undef VKP_ADDRESS_OFFSET
         }},
        {"TriangleVertices",
         sizeof(TriangleVertices),
         {VKP_O(TriangleVertices, vertex), VKP_O(TriangleVertices, attributes)}},
        {"AliasEntry",
         sizeof(AliasEntry),
         {VKP_O(AliasEntry, threshold), VKP_O(AliasEntry, alias), VKP_O(AliasEntry, probability),
          VKP_O(AliasEntry, padding)}},
        {"EnvironmentInfo",
         sizeof(EnvironmentInfo),
         {VKP_O(EnvironmentInfo, width), VKP_O(EnvironmentInfo, height),
          VKP_O(EnvironmentInfo, strength), VKP_O(EnvironmentInfo, cosRotation),
          VKP_O(EnvironmentInfo, sinRotation), VKP_O(EnvironmentInfo, color)}},
        {"SceneInfo",
         sizeof(SceneInfo),
         {VKP_O(SceneInfo, environment),
          VKP_O(SceneInfo, hasEnvironment),
          VKP_O(SceneInfo, lightCount),
          VKP_O(SceneInfo, environmentLight),
          VKP_O(SceneInfo, lightSamples),
          VKP_O(SceneInfo, maxDepth),
          VKP_O(SceneInfo, rouletteDepth),
          VKP_O(SceneInfo, seed),
          VKP_O(SceneInfo, width),
          VKP_O(SceneInfo, height),
          VKP_O(SceneInfo, clampRadiance),
          VKP_O(SceneInfo, fireflyThreshold),
          VKP_O(SceneInfo, samplerKind),
          VKP_O(SceneInfo, triangleAttributes),
          VKP_O(SceneInfo, alphaTested),
          VKP_O(SceneInfo, regularizeAlpha),
          VKP_O(SceneInfo, unsampledEmitters),
          VKP_O(SceneInfo, guideSphereCount),
          VKP_O(SceneInfo, guideFraction),
          VKP_O(SceneInfo, sampleStreams),
          VKP_O(SceneInfo, aovs),
          VKP_O(SceneInfo, microfacetCompensation),
          VKP_O(SceneInfo, treeLights),
          VKP_O(SceneInfo, media),
          VKP_O(SceneInfo, gridMedium)}},
        {"MaterialAlpha",
         sizeof(MaterialAlpha),
         {VKP_O(MaterialAlpha, mode), VKP_O(MaterialAlpha, cutoff), VKP_O(MaterialAlpha, alpha),
          VKP_O(MaterialAlpha, baseColorSlot)}},
        {"Light",
         sizeof(Light),
         {VKP_O(Light, p0), VKP_O(Light, type), VKP_O(Light, p1), VKP_O(Light, radius),
          VKP_O(Light, p2), VKP_O(Light, cosInner), VKP_O(Light, emission), VKP_O(Light, cosOuter),
          VKP_O(Light, normal), VKP_O(Light, area)}},
        {"PathVertex",
         sizeof(PathVertex),
         {VKP_O(PathVertex, position), VKP_O(PathVertex, bsdfPdf),
          VKP_O(PathVertex, specularEtaScale), VKP_O(PathVertex, normal)}},
        {"QueueCounters",
         sizeof(QueueCounters),
         {VKP_O(QueueCounters, rayCount0), VKP_O(QueueCounters, rayCount1),
          VKP_O(QueueCounters, shadowCount), VKP_O(QueueCounters, nonFinite),
          VKP_O(QueueCounters, fireflies), VKP_O(QueueCounters, rayDispatch),
          VKP_O(QueueCounters, shadowDispatch), VKP_O(QueueCounters, shadowRayCount),
          VKP_O(QueueCounters, closestRayCount), VKP_O(QueueCounters, closestRays),
          VKP_O(QueueCounters, shadowRays), VKP_O(QueueCounters, rejectedLightSamples)}},
        {"PathAov",
         sizeof(PathAov),
         {VKP_O(PathAov, albedo), VKP_O(PathAov, normal), VKP_O(PathAov, found)}},
        {"FilmAovPixel",
         sizeof(FilmAovPixel),
         {VKP_O(FilmAovPixel, albedo), VKP_O(FilmAovPixel, normal), VKP_O(FilmAovPixel, samples)}},
        {"FilmPixel",
         sizeof(FilmPixel),
         {VKP_O(FilmPixel, sum), VKP_O(FilmPixel, sumCompensation), VKP_O(FilmPixel, sumSquares),
          VKP_O(FilmPixel, sumSquaresCompensation)}},
        {"WavePush",
         sizeof(WavePush),
         {VKP_O(WavePush, firstSample), VKP_O(WavePush, firstPixel), VKP_O(WavePush, pathCount),
          VKP_O(WavePush, bounce), VKP_O(WavePush, mode), VKP_O(WavePush, filmFirstPixel),
          VKP_O(WavePush, pixelListLength), VKP_O(WavePush, listFirstEntry)}},
    };
}

TEST(SharedLayout, GlslMatchesCpp) {
    const vk::SpirvReflection reflection = vk::reflectSpirv(shaders::findKernel("layout_probe"));
    for (const Expected& e : expectedLayouts()) {
        SCOPED_TRACE(e.name);
        const auto it = reflection.structs.find(e.name);
        ASSERT_NE(it, reflection.structs.end()) << "struct not declared in layout_probe.comp";
        ASSERT_TRUE(it->second.arrayStride.has_value());
        EXPECT_EQ(*it->second.arrayStride, e.size) << "GLSL array stride differs from C++ sizeof";
        EXPECT_EQ(it->second.memberOffsets, e.offsets)
            << "GLSL member offsets differ from C++ offsetof";
    }
}

// The test must be able to fail: a struct that std430 would pad differently
// from scalar shows a different stride in the reflection of a std430 block.
TEST(SharedLayout, ReflectionSeesStd430Padding) {
    const vk::SpirvReflection reflection =
        vk::reflectSpirv(shaders::findKernel("layout_std430_probe"));
    const auto it = reflection.structs.find("ThreeVec3FourUint");
    ASSERT_NE(it, reflection.structs.end());
    ASSERT_TRUE(it->second.arrayStride.has_value());
    // Three vec3 and four 32-bit fields: 52 bytes under scalar, 64 under std430.
    EXPECT_EQ(*it->second.arrayStride, 64u);
    EXPECT_EQ(it->second.memberOffsets, (std::vector<uint32_t>{0, 16, 32, 44, 48, 52, 56}));
}

}  // namespace
