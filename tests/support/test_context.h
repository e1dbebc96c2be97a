// The Vulkan context shared by the tests of one process, created on first use
// with validation on: any validation warning or error fails the running test.
#pragma once

#include <filesystem>

#include "vk/context.h"

namespace vkpath::test {

vk::Context& context();

// ../shared/scenes/scotty3d/<name> beside the checkout.
std::filesystem::path sharedScene(const std::string& name);

// <source>/<relative>.
std::filesystem::path sourcePath(const std::string& relative);

}  // namespace vkpath::test
