// Every scene the project ships or reads (../shared/scenes/scotty3d/*.dae and
// assets/*.gltf) renders through the wavefront path tracer at low spp with
// no NaN or infinite sample and a finite, non-negative image, and its BVH
// passes the integrity check.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "bvh/bvh.h"
#include "scene/load.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"

namespace {

using namespace vkpath;

std::vector<std::string> sceneFiles() {
    std::vector<std::string> files;
    for (const auto& dir : {test::sharedScene(""), test::sourcePath("assets")})
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            const auto ext = entry.path().extension();
            if (ext == ".dae" || ext == ".gltf" || ext == ".glb") files.push_back(entry.path().string());
        }
    std::sort(files.begin(), files.end());
    return files;
}

class AllScenes : public testing::TestWithParam<std::string> {};

TEST_P(AllScenes, RenderWithoutNonFiniteSamples) {
    const scene::Scene s = scene::loadScene(GetParam());
    // The renderer's builder and options: every primitive in exactly one leaf,
    // every child box inside its parent.
    EXPECT_EQ(bvh::integrityCheck(bvh::buildBvh(s), s), std::vector<std::string>{});
    wavefront::RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    settings.samplesPerPixel = 2;
    settings.maxDepth = 4;
    settings.lightSamples = 2;
    wavefront::WavefrontRenderer renderer(test::context(), s, settings);
    const auto r = renderer.render();
    EXPECT_EQ(r.nonFiniteSamples, 0u);
    double sum = 0;
    for (const glm::vec3& p : r.image.pixels)
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(p[c]));
            ASSERT_GE(p[c], 0.0f);
            sum += p[c];
        }
    EXPECT_GT(sum, 0.0) << "the image is black";
}

INSTANTIATE_TEST_SUITE_P(Scenes, AllScenes, testing::ValuesIn(sceneFiles()),
                         [](const testing::TestParamInfo<std::string>& param) {
                             std::string name = std::filesystem::path(param.param).stem().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

}  // namespace
