#include "support/test_context.h"

#include <gtest/gtest.h>

#include <cstdlib>
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

std::filesystem::path scenesDir() {
    const char* given = std::getenv("VKPATH_SCENES_DIR");
    return std::filesystem::path(given && *given ? given : VKPATH_SCENES_DIR);
}

std::filesystem::path sharedScene(const std::string& name) {
    return scenesDir() / "scotty3d" / name;
}

std::string sharedScenesMissing() {
    const std::filesystem::path folder = scenesDir() / "scotty3d";
    std::error_code ec;
    if (std::filesystem::is_directory(folder, ec)) return {};
    return "the assignment's scenes are not here: no folder " + folder.string() +
           " (set VKPATH_SCENES_DIR, a CMake cache variable or an environment variable, to the "
           "folder "
           "holding scotty3d/; README.md, \"Scenes\")";
}

std::filesystem::path sourcePath(const std::string& relative) {
    return std::filesystem::path(VKPATH_SOURCE_DIR) / relative;
}

}  // namespace vkpath::test
