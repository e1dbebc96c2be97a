// `vkpath render --checkpoint/--resume`, stopping on SIGINT and SIGTERM, and
// outputs checked before rendering: a resumed render equals the
// uninterrupted one bit for bit (pixels and variance), a signal leaves a
// valid EXR of whole samples and a checkpoint that resumes, and a checkpoint
// of another scene, other settings or another renderer is refused with one
// line and exit code 2, writing nothing; a Vulkan error after a checkpoint
// names it.
#include "app/checkpoint.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "image/image.h"
#include "shared/dimensions.h"
#include "support/exr_metadata.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"
#include "vk/check.h"

namespace {

using namespace vkpath;
using namespace std::chrono_literals;

std::string box() {
    return test::sourcePath("assets/cornell_box.gltf").string();
}
std::string diffuseBox() {
    return test::sourcePath("assets/cornell_box_diffuse.gltf").string();
}

// Every pixel and channel equal, bit for bit (NaN never occurs in these films).
void expectSameImage(const std::string& a, const std::string& b) {
    const image::Image x = image::readImage(a), y = image::readImage(b);
    ASSERT_EQ(x.pixels.size(), y.pixels.size());
    size_t differing = 0;
    for (size_t i = 0; i < x.pixels.size(); ++i) differing += x.pixels[i] != y.pixels[i];
    EXPECT_EQ(differing, 0u) << a << " and " << b;
}

std::string render(const std::string& args) {
    const auto r = test::runVkpath("render " + args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.err;
}

class ResumeOn : public testing::TestWithParam<const char*> {};

TEST_P(ResumeOn, ResumedRenderEqualsTheUninterruptedOne) {
    const test::TempDir dir;
    const std::string common = box() + " -d 40x30 --aov variance " + GetParam();
    const std::string checkpoint = (dir / "c.ckpt").string();
    render(common + " -s 3 --checkpoint " + checkpoint + " -o " + (dir / "first.exr").string());
    EXPECT_EQ(app::readCheckpoint(checkpoint).state.samplesDone, 3u);
    render(common + " -s 7 --resume " + checkpoint + " -o " + (dir / "resumed.exr").string());
    render(common + " -s 7 -o " + (dir / "whole.exr").string());
    expectSameImage((dir / "resumed.exr").string(), (dir / "whole.exr").string());
    expectSameImage((dir / "resumed.variance.exr").string(), (dir / "whole.variance.exr").string());
    EXPECT_EQ(test::vkpathMetadata((dir / "resumed.exr").string())["vkpath:spp"], "7");
    // Not a comparison that any two renders pass: the first part differs.
    const image::Image first = image::readImage((dir / "first.exr").string());
    EXPECT_NE(first.pixels, image::readImage((dir / "whole.exr").string()).pixels);
}

INSTANTIATE_TEST_SUITE_P(Devices, ResumeOn, testing::Values("", "--device cpu"),
                         [](const auto& p) { return std::string(p.param[0] ? "Cpu" : "Gpu"); });

struct StopCase {
    int signal;
    const char* flags;
};

class StopBy : public testing::TestWithParam<StopCase> {};

// One sample per wave (768 pixels, 768 paths in flight) and a checkpoint
// after every sample: the signal comes once the first checkpoint exists, and
// the render must end within the next sample.
TEST_P(StopBy, SignalLeavesAnImageOfWholeSamplesAndACheckpointThatResumes) {
    const test::TempDir dir;
    const std::string common = box() + " -d 32x24 " + GetParam().flags;
    const std::string checkpoint = (dir / "c.ckpt").string(),
                      stopped = (dir / "stopped.exr").string();
    test::RunningVkpath running("render " + common +
                                " -s 1000000 --paths-in-flight 768 --checkpoint " + checkpoint +
                                " --checkpoint-every 0 -o " + stopped);
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    while (!std::filesystem::exists(checkpoint) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(20ms);
    ASSERT_TRUE(std::filesystem::exists(checkpoint)) << running.err();
    running.signal(GetParam().signal);
    const auto r = running.wait();
    EXPECT_EQ(r.exitCode, 128 + GetParam().signal) << r.err;
    EXPECT_NE(r.err.find("stopped by signal"), std::string::npos) << r.err;

    const app::Checkpoint c = app::readCheckpoint(checkpoint);
    const uint32_t done = c.state.samplesDone;
    ASSERT_GT(done, 0u);
    ASSERT_LT(done, 1000000u);
    EXPECT_EQ(test::vkpathMetadata(stopped)["vkpath:spp"], std::to_string(done));
    // The image so far is that many whole samples, and the checkpoint goes on to more.
    const std::string whole = (dir / "whole.exr").string(),
                      resumed = (dir / "resumed.exr").string();
    render(common + " -s " + std::to_string(done) + " -o " + whole);
    expectSameImage(stopped, whole);
    render(common + " -s " + std::to_string(done + 2) + " --resume " + checkpoint + " -o " +
           resumed);
    render(common + " -s " + std::to_string(done + 2) + " -o " + whole);
    expectSameImage(resumed, whole);
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
        EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos)
            << entry.path();
}

INSTANTIATE_TEST_SUITE_P(Signals, StopBy,
                         testing::Values(StopCase{SIGINT, ""},
                                         StopCase{SIGTERM, "--device cpu --threads 1"}),
                         [](const auto& p) {
                             return std::string(p.param.signal == SIGINT ? "SigintGpu"
                                                                         : "SigtermCpu");
                         });

// A second signal ends the render at once: a film of a million pixels and a
// few thousand paths in flight makes one sample hundreds of waves, so the
// first signal alone would take seconds to reach a whole sample.
TEST(Stop, SecondSignalExitsAtOnceWritingNothing) {
    const test::TempDir dir;
    const std::string output = (dir / "out.exr").string();
    test::RunningVkpath running("render " + box() +
                                " -d 1024x1024 -s 4 --paths-in-flight 4096 -o " + output);
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    while (running.err().find("kernels:") == std::string::npos &&
           std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(20ms);
    ASSERT_NE(running.err().find("kernels:"), std::string::npos) << running.err();
    running.signal(SIGINT);
    const auto start = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(100ms);
    running.signal(SIGINT);
    const auto r = running.wait();
    EXPECT_EQ(r.exitCode, 130) << r.err;
    EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
    EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(Checkpoint, ForeignCheckpointsAreOneLineAndNothingWritten) {
    const test::TempDir dir;
    const std::string checkpoint = (dir / "c.ckpt").string();
    render(box() + " -d 24x18 -s 2 --checkpoint " + checkpoint + " -o " + (dir / "a.exr").string());
    const std::string damaged = (dir / "damaged.ckpt").string();
    std::filesystem::copy_file(checkpoint, damaged);
    std::filesystem::resize_file(damaged, std::filesystem::file_size(damaged) - 5);
    // The same checkpoint as a build before the estimator's version wrote it:
    // its settings lack "estimator".
    const std::string older = (dir / "older.ckpt").string();
    app::Checkpoint withoutVersion = app::readCheckpoint(checkpoint);
    auto settings = nlohmann::ordered_json::parse(withoutVersion.identity.settings);
    ASSERT_EQ(settings.erase("estimator"), 1u) << withoutVersion.identity.settings;
    withoutVersion.identity.settings = settings.dump();
    app::writeCheckpoint(older, withoutVersion);
    // Settings as builds before JSON wrote them, "key=value" words.
    const std::string wordSettings = (dir / "words.ckpt").string();
    app::Checkpoint withWords = app::readCheckpoint(checkpoint);
    withWords.identity.settings = "size=24x18 max-depth=8 light-samples=1";
    app::writeCheckpoint(wordSettings, withWords);
    // A file of the format before JSON ("key value" lines), and one whose
    // header is not JSON.
    const std::string formatOne = (dir / "format1.ckpt").string();
    std::ofstream(formatOne, std::ios::binary)
        << "vkpath checkpoint 1\nscene-hash 0123456789abcdef\nsettings "
           "size=24x18 max-depth=8\n\n";
    const std::string notJson = (dir / "not_json.ckpt").string();
    std::ofstream(notJson, std::ios::binary) << "vkpath checkpoint 3\n{\"scene-hash\": \n12345678";
    struct Case {
        std::string args;
        std::string says;
    };
    const Case cases[] = {
        {diffuseBox() + " -d 24x18 --resume " + checkpoint, "from another scene"},
        {box() + " -d 24x18 -m 4 --resume " + checkpoint,
         "other settings: max-depth=8 in the checkpoint, max-depth=4 here"},
        {box() + " -d 24x18 --seed 3 --resume " + checkpoint,
         "seed=0 in the checkpoint, seed=3 here"},
        {box() + " -d 24x18 --resume " + older,
         fmt::format("other settings: nothing in the checkpoint, estimator={} here",
                     VKP_ESTIMATOR_VERSION)},
        {box() + " -d 24x18 --resume " + wordSettings,
         "written by an older vkpath build (its settings are not JSON)"},
        {box() + " -d 24x18 --resume " + formatOne,
         "a checkpoint of format 1, written by an older vkpath build"},
        {box() + " -d 24x18 --resume " + notJson,
         "damaged checkpoint: its header is not a JSON object"},
        {box() + " -d 24x18 --device cpu --resume " + checkpoint, "written by the GPU renderer"},
        {box() + " -d 24x18 --samples 5:4 --resume " + checkpoint, "samples from 0 on"},
        {box() + " -d 24x18 -s 1 --resume " + checkpoint, "more than the 1 asked"},
        {box() + " -d 24x18 --resume " + damaged, "damaged checkpoint"},
        {box() + " -d 24x18 --resume " + (dir / "a.exr").string(), "not a vkpath checkpoint"},
        {box() + " -d 24x18 --resume " + (dir / "none.ckpt").string(),
         "--resume: File does not exist"},
    };
    for (const Case& c : cases) {
        const std::string output = (dir / "out.exr").string();
        const auto r = test::runVkpath("render " + c.args + " -o " + output);
        EXPECT_EQ(r.exitCode, 2) << c.args << ": " << r.err;
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(output)) << c.args;
    }
}

TEST(RenderOutputs, UnwritableOutputsAreRefusedBeforeRendering) {
    const test::TempDir dir;
    const std::string file = (dir / "file").string();
    std::ofstream(file) << "not a folder";
    const std::string flags[] = {
        "-o " + file + "/out.exr", "-o " + (dir / "ok.exr").string() + " --png " + file + "/p.png",
        "-o " + (dir / "ok.exr").string() + " --checkpoint " + file + "/c.ckpt",
        "-o " + dir.path().string()};
    for (const std::string& f : flags) {
        const auto r = test::runVkpath("render " + box() + " -d 24x18 -s 1 " + f);
        EXPECT_EQ(r.exitCode, 2) << f << ": " << r.err;
        EXPECT_EQ(test::lineCount(r.err), 1) << r.err;
        // Before the device: nothing about kernels was said.
        EXPECT_EQ(r.err.find("kernels:"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "ok.exr")) << f;
    }
}

// A Vulkan error that ends a render after a checkpoint (the device lost: it
// cannot be provoked on lavapipe, so the error is made as VK_CHECK makes it)
// stays one line, keeps its VkResult, and says where the checkpoint is and
// how to go on.
TEST(Checkpoint, VulkanErrorAfterACheckpointIsOneLineSayingWhereItIs) {
    try {
        vk::throwVulkanError(VK_ERROR_DEVICE_LOST,
                             "vkWaitForFences(m_device, 1, &m_fence, VK_TRUE, UINT64_MAX)",
                             "host/vk/context.cpp", 470);
    } catch (const vk::VulkanError& lost) {
        const vk::VulkanError e = app::withLastCheckpoint(lost, "renders/box.ckpt", 96);
        EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
        const std::string line = e.what();
        EXPECT_EQ(line.find('\n'), std::string::npos) << line;
        EXPECT_EQ(line.rfind(lost.what(), 0), 0u) << line;
        EXPECT_NE(line.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << line;
        EXPECT_NE(line.find("; the last checkpoint, 96 spp, is in renders/box.ckpt: resume with "
                            "--resume renders/box.ckpt"),
                  std::string::npos)
            << line;
    }
}

}  // namespace
