// The command line as a user meets it: help, info, flags and exit codes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "support/run_vkpath.h"
#include "support/temp_dir.h"
#include "support/test_context.h"

namespace {

using vkpath::test::lineCount;
using vkpath::test::runVkpath;

TEST(Cli, HelpListsTheCommands) {
    const auto r = runVkpath("--help");
    EXPECT_EQ(r.exitCode, 0);
    for (const char* command : {"info", "render", "compare", "scene-info"})
        EXPECT_NE(r.out.find(command), std::string::npos) << command;
}

TEST(Cli, UnknownFlagIsOneLineAndExitTwo) {
    for (const char* args : {"--no-such-flag info", "info --no-such-flag", "no-such-command", ""}) {
        SCOPED_TRACE(args);
        const auto r = runVkpath(args);
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(lineCount(r.err), 1) << r.err;
    }
}

TEST(Cli, InfoJsonNamesTheDeviceAndItsLimits) {
    const auto r = runVkpath("--validation info --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto json = nlohmann::json::parse(r.out);
    const auto& chosen = json["chosen"];
    EXPECT_FALSE(chosen["name"].get<std::string>().empty());
    EXPECT_GT(chosen["maxStorageBufferRange"].get<uint64_t>(), 0u);
    EXPECT_GT(chosen["subgroupSize"].get<uint32_t>(), 0u);
    EXPECT_TRUE(chosen["scalarBlockLayout"].get<bool>());
    EXPECT_GE(json["devices"].size(), 1u);
}

// Whether the device traces rays in hardware from compute shaders, as
// Vulkan's own enumeration says: lavapipe from Mesa 25 (install-deps' Mesa)
// has VK_KHR_ray_query and VK_KHR_acceleration_structure.
TEST(Cli, InfoSaysWhetherTheDeviceHasRayQueries) {
    const auto r = runVkpath("info --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto chosen = nlohmann::json::parse(r.out)["chosen"];
    ASSERT_TRUE(chosen.contains("rayQuery"));
    const auto text = runVkpath("info");
    EXPECT_NE(text.out.find(chosen["rayQuery"].get<bool>() ? "ray queries       yes"
                                                           : "ray queries       no"),
              std::string::npos)
        << text.out;
    const std::string info = chosen["driverInfo"].get<std::string>();
    const size_t mesa = info.find("Mesa ");
    if (mesa != std::string::npos && chosen["driver"].get<std::string>() == "llvmpipe" &&
        std::atoi(info.c_str() + mesa + 5) >= 25) {
        EXPECT_TRUE(chosen["rayQuery"].get<bool>()) << info;
        // Measured slower there than the kernels' own traversal (docs/BENCHMARKS.md).
        EXPECT_EQ(chosen["defaultTraversal"], "compute");
    }
    EXPECT_NE(text.out.find("traversal         " + chosen["defaultTraversal"].get<std::string>()),
              std::string::npos)
        << text.out;
}

// --traversal chooses how GPU kernels trace: one line with the CPU
// reference, and one for a name it does not know.
TEST(Cli, TraversalIsAGpuChoice) {
    const vkpath::test::TempDir dir;
    for (const char* args : {"--traversal rayquery --device cpu", "--traversal hardware"}) {
        SCOPED_TRACE(args);
        const auto r = runVkpath(std::string("render ") + VKPATH_SOURCE_DIR +
                                 "/assets/cornell_box.gltf -d 8x8 -s 1 -o " +
                                 (dir.path() / "out.exr").string() + " " + args);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_EQ(lineCount(r.err), 1) << r.err;
    }
}

TEST(Cli, DeviceIndexOutOfRangeIsBadInput) {
    const auto r = runVkpath("--device-index 99 info");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    const auto env = runVkpath("info");  // the environment variable is read when the flag is absent
    EXPECT_EQ(env.exitCode, 0);
}

TEST(Cli, BadFilmSizeWritesNothing) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("vkpath-cli-bad-" + std::to_string(getpid()));
    const auto r =
        runVkpath("render " + vkpath::test::sourcePath("assets/cornell_box.gltf").string() +
                  " -d 0x5 -o " + (dir / "x.exr").string());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.exr"));
}

// A scene's bad input is one line even where the message quotes a URI or a
// name from the file that holds a newline (here a glTF buffer's URI).
TEST(Cli, BadInputQuotingANewlineIsStillOneLine) {
    const vkpath::test::TempDir dir;
    const auto scene =
        dir.write("newline.gltf",
                  R"({"asset":{"version":"2.0"},"buffers":[{"uri":"a\nb.bin","byteLength":4}]})");
    const auto r = runVkpath("render '" + scene.string() + "' -d 8x6 -s 1 -o '" +
                             (dir / "x.exr").string() + "'");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("uri 'a?b.bin' contains control characters"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.exr"));
}

}  // namespace
