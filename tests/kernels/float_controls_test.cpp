// The non-finite checks survive compilation: every stage kernel, and the test
// kernels that run the shared intersection math, declare the
// SignedZeroInfNanPreserve execution mode for 32-bit floats
// (shaders/stages/lib/float_controls.glsl), the device honours it, and the
// checks still fire at run time (FilmAccumulation.NonFiniteSamplesAreDroppedAndCounted
// feeds NaN and infinities through stage "accumulate").
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "support/test_context.h"
#include "vk/embedded_shaders.h"
#include "vk/spirv_reflect.h"

namespace {

using namespace vkpath;

// SPIR-V enumerants (unified specification, sections 3.6 and 3.31).
constexpr uint32_t EXECUTION_MODE_SIGNED_ZERO_INF_NAN_PRESERVE = 4461;
constexpr uint32_t CAPABILITY_SIGNED_ZERO_INF_NAN_PRESERVE = 4466;

bool preservesNonFinite32(std::string_view kernel) {
    const vk::SpirvReflection r = vk::reflectSpirv(shaders::findKernel(kernel));
    const bool capability = std::count(r.capabilities.begin(), r.capabilities.end(),
                                       CAPABILITY_SIGNED_ZERO_INF_NAN_PRESERVE) > 0;
    const bool mode =
        std::any_of(r.executionModes.begin(), r.executionModes.end(), [](const auto& m) {
            return m.mode == EXECUTION_MODE_SIGNED_ZERO_INF_NAN_PRESERVE &&
                   m.operands == std::vector<uint32_t>{32};
        });
    return capability && mode;
}

TEST(FloatControls, DeviceHonoursSignedZeroInfNanPreserve) {
    EXPECT_TRUE(test::context().info().signedZeroInfNanPreserveFloat32);
}

TEST(FloatControls, EveryStageKernelPreservesNanAndInfinity) {
    ASSERT_FALSE(shaders::stageKernels().empty());
    for (const shaders::EmbeddedShader& kernel : shaders::stageKernels())
        EXPECT_TRUE(preservesNonFinite32(kernel.name)) << kernel.name;
    for (const char* kernel : {"bvh_closest", "bvh_anyhit"})
        EXPECT_TRUE(preservesNonFinite32(kernel)) << kernel;
}

// The check can fail: a kernel that does not include float_controls.glsl
// does not carry the mode.
TEST(FloatControls, KernelsWithoutTheDeclarationLackTheMode) {
    EXPECT_FALSE(preservesNonFinite32("rng_fill"));
}

}  // namespace
