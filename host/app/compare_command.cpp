// `vkpath compare A.exr B.exr`: how far image A is from reference B.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <optional>

#include "app/commands.h"
#include "image/image.h"
#include "image/metrics.h"

namespace vkpath::app {
namespace {

nlohmann::json channelJson(const image::ChannelMetrics& m) {
    return {{"rmse", m.rmse},         {"relMse", m.relMse}, {"mae", m.mae}, {"maxError", m.maxError},
            {"maxAt", {m.maxX, m.maxY}}, {"psnr", std::isinf(m.psnr) ? nlohmann::json("inf") : nlohmann::json(m.psnr)}};
}

void printChannel(const char* name, const image::ChannelMetrics& m) {
    std::printf("%-8s %12.6g %12.6g %12.6g %12.6g  (%u,%u) %9.3f\n", name, m.rmse, m.relMse, m.mae, m.maxError,
                m.maxX, m.maxY, m.psnr);
}

}  // namespace

void addCompareCommand(CLI::App& app, const GlobalOptions&, Commands& commands) {
    struct Options {
        std::string a, b, heatmap;
        bool json = false;
        std::optional<double> maxRelMse, maxRmse, maxMae;
    };
    auto o = std::make_shared<Options>();
    auto* cmd = app.add_subcommand("compare", "Measure how far image A is from reference image B");
    cmd->add_option("A", o->a, "Image to judge (EXR, HDR, ...)")->required();
    cmd->add_option("B", o->b, "Reference image")->required();
    cmd->add_option("--heatmap", o->heatmap, "Write a false-colour PNG of the per-pixel relative error");
    cmd->add_flag("--json", o->json, "Print JSON");
    cmd->add_option("--max-relmse", o->maxRelMse, "Exit code 1 if the overall relative MSE exceeds this");
    cmd->add_option("--max-rmse", o->maxRmse, "Exit code 1 if the overall RMSE exceeds this");
    cmd->add_option("--max-mae", o->maxMae, "Exit code 1 if the overall mean absolute error exceeds this");
    cmd->callback([&commands, o] {
        commands.run = [o] {
            const image::Image a = image::readImage(o->a);
            const image::Image b = image::readImage(o->b);
            const image::ImageMetrics m = image::compareImages(a, b);
            if (!o->heatmap.empty()) image::writePng(o->heatmap, image::errorHeatmap(a, b));

            struct Bound {
                const char* name;
                std::optional<double> limit;
                double value;
            };
            const Bound bounds[] = {{"relMse", o->maxRelMse, m.overall.relMse},
                                    {"rmse", o->maxRmse, m.overall.rmse},
                                    {"mae", o->maxMae, m.overall.mae}};
            int code = 0;
            nlohmann::json exceeded = nlohmann::json::array();
            for (const Bound& bound : bounds)
                if (bound.limit && !(bound.value <= *bound.limit)) {
                    code = 1;
                    exceeded.push_back(bound.name);
                }
            if (m.nonFiniteA > 0 && (o->maxRelMse || o->maxRmse || o->maxMae)) {
                code = 1;  // a bound cannot be met by an image with NaN or Inf pixels
                exceeded.push_back("nonFinite");
            }

            if (o->json) {
                nlohmann::json out = {{"width", a.width},
                                      {"height", a.height},
                                      {"comparedPixels", m.comparedPixels},
                                      {"nonFiniteA", m.nonFiniteA},
                                      {"nonFiniteB", m.nonFiniteB},
                                      {"overall", channelJson(m.overall)},
                                      {"R", channelJson(m.channels[0])},
                                      {"G", channelJson(m.channels[1])},
                                      {"B", channelJson(m.channels[2])},
                                      {"exceeded", exceeded}};
                std::printf("%s\n", out.dump(2).c_str());
            } else {
                std::printf("%-8s %12s %12s %12s %12s  %s %9s\n", "channel", "RMSE", "relMSE", "MAE", "max",
                            "at", "PSNR");
                printChannel("R", m.channels[0]);
                printChannel("G", m.channels[1]);
                printChannel("B", m.channels[2]);
                printChannel("overall", m.overall);
                std::printf("non-finite pixels: %llu in A, %llu in B\n", (unsigned long long)m.nonFiniteA,
                            (unsigned long long)m.nonFiniteB);
                for (const auto& name : exceeded) std::printf("bound exceeded: %s\n", name.get<std::string>().c_str());
            }
            return code;
        };
    });
}

}  // namespace vkpath::app
