// `vkpath compare A.exr B.exr`: how far image A is from reference B; with
// --ztest, whether two renders with different seeds estimate the same image.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/commands.h"
#include "app/validators.h"
#include "image/image.h"
#include "image/metrics.h"
#include "image/statistics.h"
#include "input_error.h"

namespace vkpath::app {
namespace {

nlohmann::json channelJson(const image::ChannelMetrics& m) {
    return {{"rmse", m.rmse},
            {"relMse", m.relMse},
            {"mae", m.mae},
            {"maxError", m.maxError},
            {"maxAt", {m.maxX, m.maxY}},
            {"psnr", std::isinf(m.psnr) ? nlohmann::json("inf") : nlohmann::json(m.psnr)}};
}

void printChannel(const char* name, const image::ChannelMetrics& m) {
    std::printf("%-8s %12.6g %12.6g %12.6g %12.6g  (%u,%u) %9.3f\n", name, m.rmse, m.relMse, m.mae,
                m.maxError, m.maxX, m.maxY, m.psnr);
}

// The variance AOV of `render`: `named` if given, else the file
// `vkpath render --aov variance` writes beside it.
image::Image readVariance(const std::string& render, const std::string& named, const char* flag) {
    const std::filesystem::path path =
        named.empty() ? image::aovPath(render, "variance") : std::filesystem::path(named);
    if (!std::filesystem::is_regular_file(path))
        throw InputError(
            fmt::format("{}: no variance image (render with --aov variance, or name it with {})",
                        path.string(), flag));
    return image::readImage(path);
}

std::string formatZ(double z) {
    return std::isinf(z) ? std::string("inf") : fmt::format("{:.3f}", z);
}

// Per-block two-sample z-tests with a Sidak correction; exit code 1 when a
// block rejects "A and B estimate the same image".
int runZTest(const std::string& pathA, const std::string& pathB, const std::string& varianceA,
             const std::string& varianceB, double alpha, uint32_t blockSize, bool json) {
    const image::Image a = image::readImage(pathA);
    const image::Image b = image::readImage(pathB);
    const image::Image va = readVariance(pathA, varianceA, "--variance-a");
    const image::Image vb = readVariance(pathB, varianceB, "--variance-b");
    const image::BlockComparison c = image::compareBlocks(a, va, b, vb, blockSize, alpha);
    const bool same = c.rejected == 0;
    if (json) {
        const nlohmann::json out = {
            {"blocks", c.blocks},
            {"blockSize", blockSize},
            {"alpha", c.alpha},
            {"critical", c.critical},
            {"rejected", c.rejected},
            {"worstZ", std::isinf(c.worstZ) ? nlohmann::json("inf") : nlohmann::json(c.worstZ)},
            {"worstBlock", {c.worstX, c.worstY}},
            {"same", same}};
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("blocks: %d of %ux%u pixels\n", c.blocks, blockSize, blockSize);
        std::printf("rejected blocks: %d\n", c.rejected);
        std::printf("worst |z|: %s (block at %u,%u)\n", formatZ(c.worstZ).c_str(), c.worstX,
                    c.worstY);
        std::printf("critical |z|: %.3f (alpha %g over all blocks, Sidak-corrected)\n", c.critical,
                    c.alpha);
        std::printf("%s\n", same ? "same: no block rejects that A and B estimate the same image"
                                 : "different: A and B do not estimate the same image");
    }
    return same ? 0 : 1;
}

}  // namespace

void addCompareCommand(CLI::App& app, const GlobalOptions&, Commands& commands) {
    struct Options {
        std::string a, b, heatmap;
        bool json = false;
        std::optional<double> maxRelMse, maxRmse, maxMae;
        bool ztest = false;
        std::string varianceA, varianceB;
        double alpha = 0.01;
        uint32_t blockSize = 8;
    };
    auto o = std::make_shared<Options>();
    auto* cmd = app.add_subcommand("compare", "Measure how far image A is from reference image B");
    cmd->add_option("A", o->a, "Image to judge (EXR, HDR, ...)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("B", o->b, "Reference image")->required()->check(CLI::ExistingFile);
    cmd->add_option("--heatmap", o->heatmap,
                    "Write a false-colour PNG of the per-pixel relative error");
    cmd->add_flag("--json", o->json, "Print JSON");
    cmd->add_option("--max-relmse", o->maxRelMse,
                    "Exit code 1 if the overall relative MSE exceeds this")
        ->check(realAtLeast<double>(0));
    cmd->add_option("--max-rmse", o->maxRmse, "Exit code 1 if the overall RMSE exceeds this")
        ->check(realAtLeast<double>(0));
    cmd->add_option("--max-mae", o->maxMae,
                    "Exit code 1 if the overall mean absolute error exceeds this")
        ->check(realAtLeast<double>(0));
    auto* ztest = cmd->add_flag(
        "--ztest", o->ztest,
        "A and B are renders with different seeds: test per block whether they estimate the "
        "same image (z-tests from the variance AOVs, Sidak-corrected); exit code 1 if not");
    cmd->add_option("--variance-a", o->varianceA,
                    "Variance AOV of A (default: A.variance.exr beside A)")
        ->needs(ztest);
    cmd->add_option("--variance-b", o->varianceB,
                    "Variance AOV of B (default: B.variance.exr beside B)")
        ->needs(ztest);
    cmd->add_option("--alpha", o->alpha, "--ztest: false-alarm rate over all blocks")
        ->check(realIn<double>(1e-12, 0.5))
        ->capture_default_str()
        ->needs(ztest);
    cmd->add_option("--block", o->blockSize, "--ztest: block size in pixels")
        ->check(CLI::Range(1u, 4096u))
        ->capture_default_str()
        ->needs(ztest);
    for (const char* bound : {"--max-relmse", "--max-rmse", "--max-mae", "--heatmap"})
        ztest->excludes(cmd->get_option(bound));
    cmd->callback([&commands, o] {
        commands.run = [o] {
            if (o->ztest)
                return runZTest(o->a, o->b, o->varianceA, o->varianceB, o->alpha, o->blockSize,
                                o->json);
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
                                      {"relMseTrimmed", m.overall.relMseTrimmed},
                                      {"R", channelJson(m.channels[0])},
                                      {"G", channelJson(m.channels[1])},
                                      {"B", channelJson(m.channels[2])},
                                      {"exceeded", exceeded}};
                std::printf("%s\n", out.dump(2).c_str());
            } else {
                std::printf("%-8s %12s %12s %12s %12s  %s %9s\n", "channel", "RMSE", "relMSE",
                            "MAE", "max", "at", "PSNR");
                printChannel("R", m.channels[0]);
                printChannel("G", m.channels[1]);
                printChannel("B", m.channels[2]);
                printChannel("overall", m.overall);
                std::printf(
                    "relMSE without the %g%% of pixels with the largest error (fireflies): %.6g\n",
                    100 * image::TRIMMED_FRACTION, m.overall.relMseTrimmed);
                std::printf("non-finite pixels: %llu in A, %llu in B\n",
                            (unsigned long long)m.nonFiniteA, (unsigned long long)m.nonFiniteB);
                for (const auto& name : exceeded)
                    std::printf("bound exceeded: %s\n", name.get<std::string>().c_str());
            }
            return code;
        };
    });
}

}  // namespace vkpath::app
