// `vkpath render`'s flags and body, shared by the command line and the Python
// module (python/module.cpp), so that the same flags give the same image
// through either.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/render_options.h"
#include "wavefront/gpu_scene.h"
#include "wavefront/render_types.h"

namespace CLI {
class App;
}

namespace vkpath::app {

// The shared flags (render_options.h) and what render does with its one image.
struct RenderCommandOptions : RenderOptions {
    std::string output = "out/render.exr";
    std::string png;
    // unset: 16, or with --time-budget or --target-error as many as they allow
    std::optional<uint32_t> spp;
    std::string samples;  // --samples FIRST:COUNT (instead of -s): that range of sample indices
    std::optional<double> timeBudget;
    float exposure = 0.0f;
    std::vector<std::string> aovs;
    bool timings = false;
    std::string checkpoint;  // --checkpoint FILE
    double checkpointEvery = 300;
    std::string displayServer;  // --display-server HOST:PORT (tev)
    bool denoise = false;       // --denoise: also OUT.denoised.exr (image/denoiser.h)
    std::string resume;         // --resume FILE
    bool autoSettings = false;  // --auto: the knobs chosen by pilot renders (app/auto_search.h)
    // The knobs given as flags, which --auto keeps and does not search.
    bool givenRouletteDepth = false, givenLightSamples = false, givenSampler = false,
         givenGuideSpheres = false, givenKernel = false, givenPathsInFlight = false,
         givenLightSampler = false;
};

// Registers every flag of `vkpath render` on `cmd`, the shared ones first.
void addRenderFlags(CLI::App& cmd, RenderCommandOptions& o);

// After `cmd` parsed: records which of the knobs --auto searches were given.
void noteGivenFlags(const CLI::App& cmd, RenderCommandOptions& o);

// What a program that embeds the render (the Python module) puts in place of
// the command line's own: a scene loaded and tables built once for many
// renders, a context kept between them, its own progress and stop, and the
// result handed back rather than only written. The defaults are the command's.
struct RenderHooks {
    const scene::Scene* scene = nullptr;             // loaded with the flags' scene options already
    const wavefront::SceneTables* tables = nullptr;  // buildSceneTables(*scene): no BVH rebuild
    std::string sceneHash;  // sceneFilesHash(flags, *scene) at its load; empty: hashed now
    // In world space, instead of the scene's; the identity's "camera" setting names it.
    std::optional<scene::Camera> camera;
    vk::Context* context = nullptr;  // the device to render on (--device gpu)
    bool writeFiles = true;          // -o, --aov, --png and --denoise's files
    bool handleSignals = true;       // SIGINT/SIGTERM stop at the next whole sample (stop_signal.h)
    std::function<void(const wavefront::RenderProgress&)> progress;  // instead of the bar
    std::function<bool()> stopRequested;        // true: stop at the next whole sample
    wavefront::RenderResult* result = nullptr;  // receives the render's result
};

// The body of `vkpath render`: its exit code (0, or 128 + the signal that
// stopped it). Throws InputError on bad input.
int runRender(const GlobalOptions& global, const RenderCommandOptions& flags,
              const RenderHooks& hooks = {});

}  // namespace vkpath::app
