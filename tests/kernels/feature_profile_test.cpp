// The feature profiles (shared/feature_profiles.h): one registry for the GPU
// kernels' profiled builds (cmake/shaders.cmake, PROFILED) and the CPU
// reference's. A render runs the first profile that holds its features; each
// profiled kernel is embedded in every traversal variant and profile; and a
// profile's build has lost the code of the features outside it, which is what
// makes its pipeline faster to create (docs/BENCHMARKS.md, "Start-up").
// Images stay the same bit for bit: tests/render/all_scenes_test.cpp,
// EveryKernelGivesTheSameImage, runs the profiles' builds against the general
// kernels (--no-specialize) on every scene file.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "reference/path_sampler.h"
#include "shared/feature_profiles.h"
#include "shared/features.h"
#include "vk/embedded_shaders.h"
#include "wavefront/kernel_features.h"

namespace {

using namespace vkpath;

struct Profile {
    const char* key;
    const char* label;
    uint64_t features;
};

std::vector<Profile> registry() {
    std::vector<Profile> profiles;
#define VKP_TEST_PROFILE(NAME, key, label) \
    profiles.push_back({#key, label, uint64_t(VKP_FEATURE_PROFILE_##NAME)});
    VKP_FEATURE_PROFILES(VKP_TEST_PROFILE)
#undef VKP_TEST_PROFILE
    return profiles;
}

// The values of a module's 64-bit integer constants (OpTypeInt 64, OpConstant).
std::set<uint64_t> int64Constants(std::span<const uint32_t> spirv) {
    constexpr uint32_t OP_TYPE_INT = 21, OP_CONSTANT = 43, HEADER_WORDS = 5;
    std::set<uint32_t> int64Types;
    std::set<uint64_t> values;
    for (size_t i = HEADER_WORDS; i < spirv.size();) {
        const uint32_t opcode = spirv[i] & 0xffffu, words = spirv[i] >> 16;
        if (words == 0 || i + words > spirv.size()) {
            ADD_FAILURE() << "malformed instruction at word " << i;
            break;
        }
        if (opcode == OP_TYPE_INT && spirv[i + 2] == 64) int64Types.insert(spirv[i + 1]);
        if (opcode == OP_CONSTANT && int64Types.contains(spirv[i + 1]) && words == 5)
            values.insert(uint64_t(spirv[i + 3]) | uint64_t(spirv[i + 4]) << 32);
        i += words;
    }
    return values;
}

// Every profiled kernel's traversal variants (cmake: TRACING, PROFILED).
const std::vector<std::string> PROFILED_KERNELS = {
    "megakernel",       "megakernel_instanced", "megakernel_rayquery", "shade",
    "intersect",        "intersect_instanced",  "intersect_rayquery",  "shadow",
    "shadow_instanced", "shadow_rayquery"};

}  // namespace

TEST(FeatureProfiles, TheFirstProfileThatHoldsARendersFeaturesRunsIt) {
    const uint64_t diffuseBox = VKP_FEATURE_TRIANGLES | VKP_FEATURE_DIFFUSE |
                                VKP_FEATURE_EMISSIVE_SURFACES | VKP_FEATURE_SAMPLER_SOBOL |
                                VKP_FEATURE_LIGHT_SAMPLES | VKP_FEATURE_ROULETTE;
    EXPECT_STREQ(wavefront::featureProfile(diffuseBox), "smooth");
    EXPECT_STREQ(wavefront::featureProfile(diffuseBox | VKP_FEATURE_AOVS), "smooth_aovs");
    EXPECT_STREQ(wavefront::featureProfile(diffuseBox | VKP_FEATURE_CONDUCTOR), "core");
    EXPECT_STREQ(wavefront::featureProfile(diffuseBox | VKP_FEATURE_AOVS | VKP_FEATURE_TEXTURES),
                 "core");
    EXPECT_EQ(wavefront::featureProfile(diffuseBox | VKP_FEATURE_SHEEN), nullptr);
    EXPECT_EQ(wavefront::featureProfile(VKP_FEATURES_ALL), nullptr);
    EXPECT_EQ(wavefront::profiledKernel("shade", diffuseBox | VKP_FEATURE_CONDUCTOR), "shade_core");
    EXPECT_EQ(wavefront::profiledKernel("megakernel_instanced", diffuseBox),
              "megakernel_instanced_smooth");
    EXPECT_EQ(wavefront::profiledKernel("shade", VKP_FEATURES_ALL), "shade");

    // Narrowest first, each holding the one before it; the CPU reference
    // compiles the same list.
    const std::vector<Profile> profiles = registry();
    const auto cpu = reference::cpuProfiles();
    ASSERT_EQ(cpu.size(), profiles.size());
    for (size_t i = 0; i < profiles.size(); ++i) {
        SCOPED_TRACE(profiles[i].key);
        EXPECT_STREQ(cpu[i].name, profiles[i].label);
        EXPECT_EQ(cpu[i].features, profiles[i].features);
        EXPECT_STREQ(wavefront::featureProfile(profiles[i].features), profiles[i].key);
        if (i > 0) {
            EXPECT_EQ(profiles[i - 1].features & ~profiles[i].features, 0u);
        }
    }
}

// In a profile's build no test of a feature outside the profile is left: its
// bit is no constant of the module, where the general build tests it. The
// exception is the material kinds' bits, which materialFeature(kind) returns
// for the kind a material's data holds (a few instructions, no lobe's code).
// A profile's build is no larger than the next wider profile's.
TEST(FeatureProfiles, AProfilesBuildHasNoCodeOfTheFeaturesOutsideIt) {
    for (const std::string& kernel : PROFILED_KERNELS) {
        const std::set<uint64_t> generalConstants = int64Constants(shaders::findKernel(kernel));
        size_t narrowerSize = 0;
        for (const Profile& profile : registry()) {
            const std::string name = fmt::format("{}_{}", kernel, profile.key);
            SCOPED_TRACE(name);
            const std::span<const uint32_t> built = shaders::findKernel(name);
            EXPECT_GE(built.size(), narrowerSize);
            narrowerSize = built.size();
            const std::set<uint64_t> constants = int64Constants(built);
            int testedOutside = 0;
            for (uint32_t bit = 0; bit < VKP_FEATURE_COUNT; ++bit) {
                const uint64_t feature = VKP_FEATURE_BIT(bit);
                if ((profile.features & feature) || (VKP_FEATURES_MATERIALS & feature)) continue;
                testedOutside += generalConstants.contains(feature);
                EXPECT_FALSE(constants.contains(feature)) << "feature bit " << bit;
            }
            // The kernels that read materials test features outside every
            // profile, so the check has something to find.
            if (kernel.starts_with("megakernel") || kernel == "shade") {
                EXPECT_GT(testedOutside, 0);
            }
        }
    }
}
