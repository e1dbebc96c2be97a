// `vkpath export-mitsuba SCENE OUT_DIR [render flags]`: the scene as vkpath
// would render it with those flags, written as a Mitsuba 3 scene
// (scene/mitsuba_export.h), to be rendered by an independent renderer and
// compared with `vkpath compare`.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>

#include "app/commands.h"
#include "app/render_options.h"
#include "scene/mitsuba_export.h"
#include "shared/microfacet.h"

namespace vkpath::app {
namespace {

struct ExportOptions : RenderOptions {
    std::string outDir;
    uint32_t spp = 16;
};

int runExport(const ExportOptions& o) {
    const wavefront::RenderSettings settings = renderSettings(o, o.spp);
    const scene::Scene scene = loadRenderScene(o);

    scene::MitsubaExportSettings exportSettings;
    exportSettings.width = settings.width;
    exportSettings.height = settings.height;
    exportSettings.samplesPerPixel = settings.samplesPerPixel;
    exportSettings.maxDepth = settings.maxDepth;
    exportSettings.rouletteDepth = settings.rouletteDepth;
    exportSettings.seed = settings.seed;
    const scene::MitsubaExportResult result = scene::exportMitsuba(scene, exportSettings, o.outDir);

    std::vector<std::string> warnings = result.warnings;
    if (settings.lightSamples != 1)
        warnings.push_back(
            fmt::format("-l {}: Mitsuba's path tracer takes one light sample per vertex (the same "
                        "image in expectation, with other noise)",
                        settings.lightSamples));
    if (settings.clampRadiance > 0)
        warnings.push_back(
            "--clamp: Mitsuba's path tracer does not clamp; the exported scene renders unclamped");
    const auto rough = [](const scene::Material& m) {
        return (scene::materialKindInfo(m.kind).flags & VKP_KIND_MICROFACET) != 0 &&
               m.roughness * m.roughness >= VKP_MICROFACET_SMOOTH_ALPHA;
    };
    if (settings.microfacetCompensation &&
        std::any_of(scene.materials.begin(), scene.materials.end(), rough))
        warnings.push_back(
            "Mitsuba's rough conductors and dielectrics scatter once: they render darker than "
            "vkpath's compensated lobes; compare with `vkpath render --single-scattering`");
    if (settings.regularize > 0)
        warnings.push_back(
            "--regularize: Mitsuba's path tracer does not regularise; the exported scene renders "
            "unregularised");
    for (const std::string& warning : warnings)
        std::fprintf(stderr, "vkpath: warning: %s\n", warning.c_str());
    std::printf("%s\n", result.xml.string().c_str());
    return 0;
}

}  // namespace

void addExportMitsubaCommand(CLI::App& app, const GlobalOptions&, Commands& commands) {
    auto o = std::make_shared<ExportOptions>();
    auto* cmd = app.add_subcommand(
        "export-mitsuba",
        "Write the scene, as render would see it with the same flags, as a Mitsuba 3 "
        "scene (OUT_DIR/scene.xml, PLY meshes)");
    addRenderOptions(*cmd, *o);
    cmd->add_option("out_dir", o->outDir, "Output folder")->required();
    cmd->add_option("-s,--spp", o->spp, "Samples per pixel of Mitsuba's sampler")
        ->check(CLI::Range(1u, UINT32_MAX))
        ->capture_default_str();
    cmd->callback([&commands, o] { commands.run = [o] { return runExport(*o); }; });
}

}  // namespace vkpath::app
