// `vkpath render --sampler`: the flag reaches both devices (the same seed
// gives the same image on CPU and GPU, and another image than the
// independent sampler), the EXR records it, and a bad name is refused.
#include <gtest/gtest.h>

#include <string>

#include "image/image.h"
#include "image/metrics.h"
#include "support/exr_metadata.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using namespace vkpath;

std::string sceneArgument() {
    return test::sourcePath("assets/cornell_box_diffuse.gltf").string();
}

std::string samplerMetadata(const std::string& path) {
    return test::vkpathMetadata(path)["vkpath:sampler"];
}

TEST(SamplerCli, SobolOnBothDevicesAndRecordedInTheExr) {
    const test::TempDir dir;
    auto render = [&](const std::string& name, const std::string& flags) {
        const std::string path = (dir / name).string();
        const auto r = test::runVkpath("render " + sceneArgument() + " -d 24x18 -s 4 --seed 3 -o " +
                                       path + " " + flags);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return path;
    };
    const std::string gpu = render("gpu.exr", "--sampler sobol");
    const std::string cpu = render("cpu.exr", "--sampler sobol --device cpu");
    const std::string independent = render("independent.exr", "--sampler independent --device cpu");
    const std::string byDefault = render("default.exr", "");
    EXPECT_EQ(samplerMetadata(gpu), "sobol");
    EXPECT_EQ(samplerMetadata(cpu), "sobol");
    EXPECT_EQ(samplerMetadata(independent), "independent");
    EXPECT_EQ(samplerMetadata(byDefault), "sobol") << "the default (docs/TRADEOFFS.md)";
    // Same paths (reference_renderer_test.cpp's bound for this scene), and not the independent
    // ones.
    const image::Image g = image::readImage(gpu), c = image::readImage(cpu),
                       i = image::readImage(independent);
    EXPECT_LE(image::compareImages(c, g).overall.relMse, 1e-3);
    EXPECT_GT(image::compareImages(i, g).overall.relMse, 1e-2);
}

TEST(SamplerCli, UnknownSamplerIsOneLineAndExitTwo) {
    const auto r =
        test::runVkpath("render " + sceneArgument() + " -d 8x8 -s 1 --sampler halton -o /dev/null");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
}

}  // namespace
