#include "support/test_context.h"

#include <gtest/gtest.h>

#include <memory>

namespace vkpath::test {
namespace {
std::unique_ptr<vk::Context> g_context;
}

vk::Context& context() {
    if (!g_context) {
        vk::ContextOptions options;
        options.validation = true;
        // The layer calls back inside the offending Vulkan call, so the
        // failure lands on the test that made it.
        options.onValidationMessage = [](const char* message) {
            ADD_FAILURE() << "Vulkan validation: " << message;
        };
        g_context = std::make_unique<vk::Context>(options);
    }
    return *g_context;
}

std::filesystem::path sharedScene(const std::string& name) {
    return std::filesystem::path(VKPATH_SHARED_SCENES) / "scotty3d" / name;
}

std::filesystem::path sourcePath(const std::string& relative) {
    return std::filesystem::path(VKPATH_SOURCE_DIR) / relative;
}

}  // namespace vkpath::test
