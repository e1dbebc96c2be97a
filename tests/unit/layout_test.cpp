// Every struct in shaders/shared/ must have the same layout in GLSL (scalar
// block layout, read from the SPIR-V of tests/kernels/layout_probe.comp) and
// in C++ (offsetof, sizeof). Nothing else would notice a mismatch.
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "shared/bindings.h"
#include "shared/camera.h"
#include "shared/material.h"
#include "shared/ray.h"
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

std::vector<Expected> expectedLayouts() {
    return {
        {"Ray", sizeof(Ray),
         {VKP_OFFSET(Ray, origin), VKP_OFFSET(Ray, tMax), VKP_OFFSET(Ray, direction), VKP_OFFSET(Ray, pixel)}},
        {"Camera", sizeof(Camera),
         {VKP_OFFSET(Camera, origin), VKP_OFFSET(Camera, forward), VKP_OFFSET(Camera, right),
          VKP_OFFSET(Camera, up), VKP_OFFSET(Camera, width), VKP_OFFSET(Camera, height)}},
        {"GeneratePush", sizeof(GeneratePush),
         {VKP_OFFSET(GeneratePush, firstPixel), VKP_OFFSET(GeneratePush, count),
          VKP_OFFSET(GeneratePush, sampleIndex), VKP_OFFSET(GeneratePush, seed)}},
        {"Material", sizeof(Material),
         {VKP_OFFSET(Material, reflectance), VKP_OFFSET(Material, kind), VKP_OFFSET(Material, transmittance),
          VKP_OFFSET(Material, ior), VKP_OFFSET(Material, emission)}},
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
        EXPECT_EQ(it->second.memberOffsets, e.offsets) << "GLSL member offsets differ from C++ offsetof";
    }
}

// The test must be able to fail: a struct that std430 would pad differently
// from scalar shows a different stride in the reflection of a std430 block.
TEST(SharedLayout, ReflectionSeesStd430Padding) {
    const vk::SpirvReflection reflection = vk::reflectSpirv(shaders::findKernel("layout_std430_probe"));
    const auto it = reflection.structs.find("ThreeVec3FourUint");
    ASSERT_NE(it, reflection.structs.end());
    ASSERT_TRUE(it->second.arrayStride.has_value());
    // Three vec3 and four 32-bit fields: 52 bytes under scalar, 64 under std430.
    EXPECT_EQ(*it->second.arrayStride, 64u);
    EXPECT_EQ(it->second.memberOffsets, (std::vector<uint32_t>{0, 16, 32, 44, 48, 52, 56}));
}

}  // namespace
