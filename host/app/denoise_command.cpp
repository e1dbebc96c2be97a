// `vkpath denoise IN.exr [--albedo A.exr [--normal N.exr]] -o OUT.exr [--png P.png]`: Intel
// Open Image Denoise on a render (image/denoiser.h); the output keeps the
// input's vkpath metadata and says it is denoised.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "app/commands.h"
#include "image/denoiser.h"
#include "image/image.h"
#include "input_error.h"

namespace vkpath::app {
namespace {

struct DenoiseOptions {
    std::string input;
    std::string albedo;
    std::string normal;
    std::string output;
    std::string png;  // --png: also an sRGB preview of the denoised image
    bool prefilter = false;
};

int runDenoise(const DenoiseOptions& o) {
    image::loadDenoiser();  // a missing library: one line before any work
    const image::Image color = image::readImage(o.input);
    std::optional<image::Image> albedo, normal;
    auto guide = [&](const std::string& path, const char* what) {
        image::Image g = image::readImage(path);
        if (g.width != color.width || g.height != color.height)
            throw InputError(fmt::format("{}: the {} guide is {}x{}, the image ({}) {}x{}", path,
                                         what, g.width, g.height, o.input, color.width,
                                         color.height));
        return g;
    };
    if (!o.albedo.empty()) albedo = guide(o.albedo, "albedo");
    if (!o.normal.empty()) normal = guide(o.normal, "normal");
    const image::DenoiseInputs inputs{&color, albedo ? &*albedo : nullptr,
                                      normal ? &*normal : nullptr, o.prefilter};
    const image::Denoised denoised = image::denoise(inputs);
    image::Metadata metadata;
    for (const auto& [key, value] : image::readVkpathMetadata(o.input))
        metadata.emplace_back(key, value);
    metadata.emplace_back("vkpath:denoised", image::denoisedMetadata(inputs));
    image::writeExr(o.output, denoised.image, metadata);
    std::fprintf(stderr, "denoised %s in %.3f s (%s)\n", o.input.c_str(), denoised.seconds,
                 denoised.library.c_str());
    std::printf("%s\n", o.output.c_str());
    if (!o.png.empty()) {
        image::writePng(o.png, denoised.image);
        std::printf("%s\n", o.png.c_str());
    }
    return 0;
}

}  // namespace

void addDenoiseCommand(CLI::App& app, const GlobalOptions&, Commands& commands) {
    auto o = std::make_shared<DenoiseOptions>();
    auto* cmd = app.add_subcommand(
        "denoise",
        "Denoise a render with Intel Open Image Denoise 2 (pip install pyoidn; or "
        "VKPATH_OIDN_LIBRARY=path/to/libOpenImageDenoise.so.2)");
    cmd->add_option("input", o->input, "The render's EXR")->required()->check(CLI::ExistingFile);
    auto* albedo = cmd->add_option("--albedo", o->albedo, "Albedo guide EXR (same size)")
                       ->check(CLI::ExistingFile);
    cmd->add_option("--normal", o->normal, "Shading-normal guide EXR (same size; needs --albedo)")
        ->check(CLI::ExistingFile)
        ->needs(albedo);
    cmd->add_option("-o,--output", o->output, "The denoised EXR")->required();
    cmd->add_flag("--prefilter", o->prefilter,
                  "Denoise the guides first and declare them clean (OIDN's cleanAux)")
        ->needs(albedo);
    cmd->add_option("--png", o->png, "Also write an sRGB PNG preview of the denoised image");
    cmd->callback([&commands, o] { commands.run = [o] { return runDenoise(*o); }; });
}

}  // namespace vkpath::app
