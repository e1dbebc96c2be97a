// `vkpath info`: the devices, the chosen one, and the limits that matter.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "bvh/gpu_bvh.h"
#include "vk/context.h"
#include "wavefront/wave_sizing.h"

namespace vkpath::app {
namespace {

nlohmann::json deviceJson(const vk::DeviceInfo& d) {
    return {
        {"index", d.index},
        {"name", d.name},
        {"type", d.type},
        {"driver", d.driverName},
        {"driverInfo", d.driverInfo},
        {"vulkanVersion", d.apiVersionString()},
        {"maxWorkgroupSize", d.maxWorkgroupSize},
        {"maxWorkgroupCount", d.maxWorkgroupCount},
        {"maxWorkgroupInvocations", d.maxWorkgroupInvocations},
        {"maxStorageBufferRange", d.maxStorageBufferRange},
        {"maxPushConstantsSize", d.maxPushConstantsSize},
        {"subgroupSize", d.subgroupSize},
        {"shaderFloat64", d.shaderFloat64},
        {"shaderInt64", d.shaderInt64},
        {"scalarBlockLayout", d.scalarBlockLayout},
        {"bufferDeviceAddress", d.bufferDeviceAddress},
        {"signedZeroInfNanPreserveFloat32", d.signedZeroInfNanPreserveFloat32},
        {"rayQuery", d.rayQuery},
        {"defaultTraversal", bvh::traversalName(wavefront::defaultTraversal(d))},
        {"timestamps", d.timestamps},
        {"timestampPeriodNs", d.timestampPeriodNs},
        {"deviceLocalMemory", d.deviceLocalMemory},
        {"advice", vk::driverAdvice(d)},
    };
}

void printDevice(const vk::DeviceInfo& d) {
    auto yesNo = [](bool b) { return b ? "yes" : "no"; };
    std::printf("  driver            %s (%s)\n", d.driverName.c_str(), d.driverInfo.c_str());
    std::printf("  Vulkan            %s\n", d.apiVersionString().c_str());
    std::printf("  max workgroup     %u x %u x %u, %u invocations\n", d.maxWorkgroupSize[0],
                d.maxWorkgroupSize[1], d.maxWorkgroupSize[2], d.maxWorkgroupInvocations);
    std::printf("  max storage range %llu bytes (%.0f MiB)\n",
                static_cast<unsigned long long>(d.maxStorageBufferRange),
                d.maxStorageBufferRange / 1048576.0);
    std::printf("  subgroup size     %u\n", d.subgroupSize);
    std::printf("  float64 / int64   %s / %s\n", yesNo(d.shaderFloat64), yesNo(d.shaderInt64));
    std::printf("  timestamps        %s, period %g ns\n", yesNo(d.timestamps), d.timestampPeriodNs);
    std::printf("  ray queries       %s\n",
                d.rayQuery ? "yes (VK_KHR_ray_query, VK_KHR_acceleration_structure)" : "no");
    std::printf("  traversal         %s by default (--traversal)\n",
                bvh::traversalName(wavefront::defaultTraversal(d)));
    std::printf("  device memory     %.0f MiB\n", d.deviceLocalMemory / 1048576.0);
    const std::string advice = vk::driverAdvice(d);
    if (!advice.empty()) std::printf("  note              %s\n", advice.c_str());
}

}  // namespace

void addInfoCommand(CLI::App& app, const GlobalOptions& global, Commands& commands) {
    auto* cmd =
        app.add_subcommand("info", "Print the Vulkan devices, the chosen one and its limits");
    auto json = std::make_shared<bool>(false);
    cmd->add_flag("--json", *json, "Print JSON instead of text");
    cmd->callback([&global, &commands, json] {
        commands.run = [&global, json] {
            return withContext(global, [&](vk::Context& context) {
                const auto devices = vk::listDevices();
                const vk::DeviceInfo& chosen = context.info();
                if (*json) {
                    nlohmann::json all = nlohmann::json::array();
                    for (const auto& d : devices) all.push_back(deviceJson(d));
                    nlohmann::json out = {{"vkpathVersion", VKPATH_VERSION},
                                          {"chosen", deviceJson(chosen)},
                                          {"devices", all}};
                    std::printf("%s\n", out.dump(2).c_str());
                    return 0;
                }
                std::printf("vkpath %s\n", VKPATH_VERSION);
                std::printf("device %u: %s (%s)  [chosen]\n", chosen.index, chosen.name.c_str(),
                            chosen.type.c_str());
                printDevice(chosen);
                for (const auto& d : devices)
                    if (d.index != chosen.index)
                        std::printf("device %u: %s (%s)\n", d.index, d.name.c_str(),
                                    d.type.c_str());
                return 0;
            });
        };
    });
}

}  // namespace vkpath::app
