// Subcommands of the vkpath command line. Each add*Command registers its
// flags on `app` and sets commands.run to its body when it is chosen.
#pragma once

#include <functional>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace vkpath::vk {
struct ContextOptions;
class Context;
}  // namespace vkpath::vk

namespace vkpath::scene {
struct Scene;
}

namespace vkpath::app {

struct GlobalOptions {
    bool validation = false;
    std::optional<uint32_t> deviceIndex;
};

struct Commands {
    std::function<int()> run;
};

// Runs `body` with a context made from the global options; with validation
// on, any validation message turns a success into exit code 1.
int withContext(const GlobalOptions& global, const std::function<int(vk::Context&)>& body);

void addInfoCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addRenderCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addConvergeCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addCompareCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addSceneInfoCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addExportMitsubaCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addMergeCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);
void addDenoiseCommand(CLI::App& app, const GlobalOptions& global, Commands& commands);

// What `vkpath scene-info FILE --json` prints for `scene`, loaded from `file`.
std::string sceneInfoJson(const std::string& file, const scene::Scene& scene);

}  // namespace vkpath::app
