// Which build of the CPU reference's integrator a render runs
// (reference/path_sampler.h): the first profile of shared/feature_profiles.h
// that holds the render's features, else the general code. That the builds
// give the same image is tests/render/all_scenes_test.cpp's
// TheCpuProfileGivesTheSameImage.
#include "reference/path_sampler.h"

#include <gtest/gtest.h>

#include <bit>

#include "reference/reference_renderer.h"
#include "shared/features.h"
#include "support/test_scenes.h"
#include "wavefront/kernel_features.h"

namespace {

using namespace vkpath;

constexpr uint64_t DEFINED = VKP_FEATURE_BIT(VKP_FEATURE_COUNT) - 1;

TEST(CpuProfiles, AreProperSubsetsFewestFeaturesFirst) {
    const auto profiles = reference::cpuProfiles();
    ASSERT_FALSE(profiles.empty());
    for (size_t i = 0; i < profiles.size(); ++i) {
        SCOPED_TRACE(profiles[i].name);
        EXPECT_EQ(profiles[i].features & ~DEFINED, 0u) << "a bit no feature has";
        EXPECT_NE(profiles[i].features, DEFINED) << "the general code already holds every feature";
        if (i > 0) {
            EXPECT_LE(std::popcount(profiles[i - 1].features), std::popcount(profiles[i].features));
        }
    }
}

// The smooth profile holds the Scotty3D scenes' features; a conductor is
// outside it (the core profile holds it), and so is path regularisation; a
// sheen is outside every profile.
TEST(CpuProfiles, ARenderRunsTheProfileThatHoldsItsFeatures) {
    wavefront::RenderSettings settings;
    settings.width = 8;
    settings.height = 6;
    const scene::Scene glass =
        test::sphereInEnvironment(scene::MaterialKind::Dielectric, glm::vec3(0.5f));
    const reference::ReferenceRenderer smooth(glass, settings);
    EXPECT_STREQ(smooth.sampler().name(), "smooth");
    EXPECT_EQ(smooth.features() & ~smooth.sampler().features(), 0u);
    EXPECT_NE(smooth.describe().find("'smooth' profile"), std::string::npos) << smooth.describe();

    const scene::Scene conductor =
        test::sphereInEnvironment(scene::MaterialKind::Conductor, glm::vec3(0.5f));
    const reference::ReferenceRenderer rough(conductor, settings);
    EXPECT_NE(rough.features() & VKP_FEATURE_CONDUCTOR, 0u);
    EXPECT_STREQ(rough.sampler().name(), "core");

    scene::Scene sheened =
        test::sphereInEnvironment(scene::MaterialKind::MetallicRoughness, glm::vec3(0.5f));
    sheened.materials[0].sheenColor = glm::vec3(1.0f);
    const reference::ReferenceRenderer cloth(sheened, settings);
    EXPECT_EQ(cloth.sampler().features(), VKP_FEATURES_ALL);
    EXPECT_NE(cloth.describe().find("no profile holds"), std::string::npos) << cloth.describe();

    settings.regularize = 0.2f;
    const scene::Scene mirror =
        test::sphereInEnvironment(scene::MaterialKind::Mirror, glm::vec3(0.5f));
    const reference::ReferenceRenderer regularized(mirror, settings);
    EXPECT_NE(regularized.features() & VKP_FEATURE_REGULARIZE, 0u);
    EXPECT_STREQ(regularized.sampler().name(), "core");

    settings.regularize = 0.0f;
    settings.specialize = false;
    const reference::ReferenceRenderer general(glass, settings);
    EXPECT_STREQ(general.sampler().name(), "general");
    EXPECT_NE(general.describe().find("--no-specialize"), std::string::npos) << general.describe();
}

}  // namespace
