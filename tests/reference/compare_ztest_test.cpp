// `vkpath render --device cpu` and `vkpath compare --ztest` as a user runs
// them: renders with the variance AOV, the z-test's verdict as an exit code,
// and one-line errors for what is missing.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image/statistics.h"
#include "reference/reference_renderer.h"
#include "scene/load.h"
#include "support/run_vkpath.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;

class CompareZTest : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        s_dir =
            std::filesystem::temp_directory_path() / ("vkpath-ztest-" + std::to_string(getpid()));
        std::filesystem::create_directories(s_dir);
        // Two seeds of the diffuse box and one of the other box, rendered
        // in-process by the CPU reference (GPU against CPU is
        // reference_renderer_test's) and written as `render --aov variance`
        // writes them; CpuRenderWrites... checks that the command line
        // writes the same.
        const scene::Scene diffuse =
            scene::loadScene(test::sourcePath("assets/cornell_box_diffuse.gltf"));
        const scene::Scene other = scene::loadScene(test::sourcePath("assets/cornell_box.gltf"));
        write(diffuse, 1, "a.exr");
        write(diffuse, 2, "cpu.exr");
        write(other, 3, "other.exr");
    }
    static wavefront::RenderSettings settings(uint32_t seed) {
        wavefront::RenderSettings s;
        s.width = 32;
        s.height = 24;
        s.samplesPerPixel = 32;
        s.maxDepth = 3;
        s.seed = seed;
        return s;
    }
    static void write(const scene::Scene& scene, uint32_t seed, const char* name) {
        const auto r = reference::ReferenceRenderer(scene, settings(seed)).render();
        image::writeExr(file(name), r.image);
        image::writeExr(image::aovPath(file(name), "variance"), r.varianceOfMean);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(s_dir); }
    static std::string file(const char* name) { return (s_dir / name).string(); }

    static inline std::filesystem::path s_dir;
};

TEST_F(CompareZTest, CpuRenderWritesTheImageTheVarianceAndASummary) {
    const auto r = test::runVkpath(
        "render " + test::sourcePath("assets/cornell_box_diffuse.gltf").string() +
        " -d 32x24 -s 32 -m 3 --seed 2 --aov variance --device cpu -t 3 -o " + file("cli.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("cli.exr"), std::string::npos);
    EXPECT_NE(r.out.find("cli.variance.exr"), std::string::npos);
    EXPECT_NE(r.err.find("CPU reference (3 threads)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Mpaths/s"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Mrays/s"), std::string::npos) << r.err;
    // The same pixels as the in-process render (hardware threads): any thread count gives the same
    // image.
    for (const char* suffix : {".exr", ".variance.exr"}) {
        SCOPED_TRACE(suffix);
        const image::Image cli = image::readImage(s_dir / (std::string("cli") + suffix));
        const image::Image lib = image::readImage(s_dir / (std::string("cpu") + suffix));
        ASSERT_EQ(cli.width, 32u);
        ASSERT_EQ(cli.height, 24u);
        EXPECT_EQ(std::memcmp(cli.pixels.data(), lib.pixels.data(),
                              cli.pixels.size() * sizeof(glm::vec3)),
                  0);
    }
}

TEST_F(CompareZTest, AcceptsTheSameSceneWithDifferentSeeds) {
    const auto r = test::runVkpath("compare --ztest " + file("a.exr") + " " + file("cpu.exr"));
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    for (const char* line : {"blocks: 12", "rejected blocks: 0", "worst |z|", "critical |z|"})
        EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
}

TEST_F(CompareZTest, RejectsADifferentScene) {
    const auto r =
        test::runVkpath("compare --ztest " + file("cpu.exr") + " " + file("other.exr") + " --json");
    EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
    const auto json = nlohmann::json::parse(r.out);
    EXPECT_GT(json["rejected"].get<int>(), 0);
    EXPECT_EQ(json["blocks"].get<int>(), 12);
    EXPECT_FALSE(json["same"].get<bool>());
    EXPECT_GT(json["worstZ"].get<double>(), json["critical"].get<double>());
}

TEST_F(CompareZTest, AlphaAndBlockSizeChangeTheTest) {
    const auto r = test::runVkpath("compare --ztest " + file("a.exr") + " " + file("cpu.exr") +
                                   " --alpha 0.05 --block 4 --json");
    ASSERT_EQ(r.exitCode == 0 || r.exitCode == 1, true) << r.err;
    const auto json = nlohmann::json::parse(r.out);
    EXPECT_EQ(json["blocks"].get<int>(), 48);
    EXPECT_DOUBLE_EQ(json["alpha"].get<double>(), 0.05);
}

TEST_F(CompareZTest, VarianceFilesCanBeNamed) {
    std::filesystem::copy_file(file("cpu.variance.exr"), file("elsewhere.exr"),
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy_file(file("cpu.exr"), file("lonely.exr"),
                               std::filesystem::copy_options::overwrite_existing);
    const auto r = test::runVkpath("compare --ztest " + file("a.exr") + " " + file("lonely.exr") +
                                   " --variance-b " + file("elsewhere.exr"));
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
}

TEST_F(CompareZTest, MissingVarianceIsOneLineAndExitTwo) {
    std::filesystem::copy_file(file("cpu.exr"), file("novariance.exr"),
                               std::filesystem::copy_options::overwrite_existing);
    for (const std::string& args :
         {"compare --ztest " + file("novariance.exr") + " " + file("a.exr"),
          "compare --ztest " + file("a.exr") + " " + file("novariance.exr"),
          "compare --ztest " + file("a.exr") + " " + file("cpu.exr") + " --variance-a " +
              file("missing.exr")}) {
        SCOPED_TRACE(args);
        const auto r = test::runVkpath(args);
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        EXPECT_NE(r.err.find("variance"), std::string::npos) << r.err;
        EXPECT_TRUE(r.out.empty());
    }
}

// Flag errors are found before any file is read.
TEST(CompareZTestFlags, BadFlagsAreOneLineAndExitTwo) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("vkpath-ztest-flags-" + std::to_string(getpid()));
    auto file = [&](const char* name) { return (dir / name).string(); };
    for (const std::string& args :
         {"compare " + file("a.exr") + " " + file("cpu.exr") +
              " --alpha 0.05",  // --alpha needs --ztest
          "compare --ztest " + file("a.exr") + " " + file("cpu.exr") + " --max-rmse 1",
          "compare --ztest " + file("a.exr") + " " + file("cpu.exr") + " --alpha 2",
          "render " + test::sourcePath("assets/cornell_box.gltf").string() + " -t 2 -o " +
              file("x.exr"),
          "render " + test::sourcePath("assets/cornell_box.gltf").string() + " --device tpu -o " +
              file("x.exr")}) {
        SCOPED_TRACE(args);
        const auto r = test::runVkpath(args);
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(file("x.exr")));
}

}  // namespace
