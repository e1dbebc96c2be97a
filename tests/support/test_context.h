// The Vulkan context shared by the tests of one process, created on first use
// with validation on: any validation warning or error fails the running test.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "vk/context.h"

namespace vkpath::test {

vk::Context& context();

// The assignment's scene folder: the environment variable VKPATH_SCENES_DIR
// where set, else the CMake cache variable of that name (by default
// ../shared/scenes beside the checkout).
std::filesystem::path scenesDir();

// <scenes folder>/scotty3d/<name>.
std::filesystem::path sharedScene(const std::string& name);

// Empty where <scenes folder>/scotty3d is a folder; otherwise the reason a
// test that reads it skips, naming the folder and the variable.
std::string sharedScenesMissing();

// <source>/<relative>.
std::filesystem::path sourcePath(const std::string& relative);

}  // namespace vkpath::test

// Skips the running test, with the reason, where the assignment's scenes are
// absent. In a test body (or a function it calls that returns void).
#define VKPATH_SKIP_WITHOUT_SHARED_SCENES()                                      \
    do {                                                                         \
        const std::string vkpathMissing = ::vkpath::test::sharedScenesMissing(); \
        if (!vkpathMissing.empty()) GTEST_SKIP() << vkpathMissing;               \
    } while (0)
