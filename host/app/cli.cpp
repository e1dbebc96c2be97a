#include "app/cli.h"

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "app/commands.h"
#include "input_error.h"
#include "vk/check.h"

namespace vkpath::app {
namespace {

bool environmentFlag(const char* name) {
    const char* value = std::getenv(name);
    return value && *value && std::string(value) != "0";
}

// Mesa's drivers warn when XDG_RUNTIME_DIR is unset (headless machines, CI);
// give them a private directory instead of asking the user to set one.
void prepareHeadlessEnvironment() {
    if (std::getenv("XDG_RUNTIME_DIR")) return;
    std::string dir = fmt::format("/tmp/vkpath-runtime-{}", static_cast<long>(getuid()));
    std::filesystem::create_directories(dir);
    std::filesystem::permissions(dir, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::replace);
    setenv("XDG_RUNTIME_DIR", dir.c_str(), 0);
}

}  // namespace

int runCli(int argc, char** argv) {
    CLI::App app{"vkpath: a physically based path tracer on Vulkan compute", "vkpath"};
    app.require_subcommand(1);
    app.set_version_flag("--version", VKPATH_VERSION);

    GlobalOptions global;
    global.validation = environmentFlag("VKPATH_VALIDATION");
    app.add_flag("--validation", global.validation,
                 "Enable Vulkan validation; any validation message makes the exit code 1 "
                 "(also VKPATH_VALIDATION=1)");
    app.add_option("--device-index", global.deviceIndex,
                   "Vulkan device to use, as listed by `vkpath info` (also VKPATH_DEVICE_INDEX)");

    Commands commands;
    addInfoCommand(app, global, commands);
    addRenderCommand(app, global, commands);
    addConvergeCommand(app, global, commands);
    addCompareCommand(app, global, commands);
    addSceneInfoCommand(app, global, commands);
    addExportMitsubaCommand(app, global, commands);
    addMergeCommand(app, global, commands);
    addDenoiseCommand(app, global, commands);

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "vkpath: %s (see vkpath --help)\n", e.what());
        return 2;
    }

    try {
        prepareHeadlessEnvironment();
        return commands.run();
    } catch (const InputError& e) {
        // One line whatever the file said: a name or URI read from it may hold a newline.
        std::string message = e.what();
        for (char& c : message)
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
        std::fprintf(stderr, "vkpath: %s\n", message.c_str());
        return 2;
    } catch (const vk::VulkanError& e) {
        std::fprintf(stderr, "vkpath: Vulkan error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vkpath: error: %s\n", e.what());
        return 1;
    }
}

}  // namespace vkpath::app
