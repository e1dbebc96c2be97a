// `vkpath render --auto`: short pilot renders choose, for this scene and
// device, the knobs that change how fast the image converges and never what
// it converges to (docs/TRADEOFFS.md, "Settings chosen by measurement"):
// the kernel form and paths in flight (time only: the same image), the
// sampler, light samples per vertex, the sphere-guiding fraction and the
// roulette depth (time and variance, never the expectation).
//
// A setting's figure of merit is its efficiency, 1 / (seconds x relMSE) of
// one render: the inverse of its time to any error. The error of a pilot is
// estimated from two pilots with different seeds (measurePair), honest for
// the Sobol' sampler too, whose per-pixel sample variance overstates it. The
// search is coordinate descent over a short candidate list per knob, in order
// of expected effect, each knob's list left at its first candidate that does
// not clearly win, and the whole search left where the next pilot would
// spend more than 5% of the render's budget.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "app/auto_choice.h"
#include "image/image.h"
#include "wavefront/render_types.h"

namespace vkpath::app {

// One pilot: its image, its render time (the renderer's own loop, wall
// seconds: what the budget counts), the time settings are compared by, and
// the time building its renderer took (scene upload, pipelines).
//
// The comparison time is the process's CPU time on a CPU device (lavapipe,
// --device cpu): on a machine shared with other work the wall clock of a
// pilot of milliseconds varied 2x from one pilot to the next, its CPU time
// far less. On a GPU it is the device's time (the stages' timestamps).
struct PilotRender {
    image::Image image;
    double seconds = 0;
    double costSeconds = 0;
    double setupSeconds = 0;
};
using PilotRenderer = std::function<PilotRender(const wavefront::RenderSettings&)>;

// What a pair of pilots (the same settings, different seeds) says.
struct PilotMeasurement {
    double seconds = 0;  // one render's comparison time (PilotRender::costSeconds; the pair's mean)
    // One render's relMSE (compare's definition), estimated from the pair:
    // the mean over pixels of mean_c (a - b)^2 / 2 / (m^2 + 0.01), m = (a + b) / 2
    // (E[(a - b)^2] = 2 Var for independent renders), and its standard error
    // over the pixels.
    double relMse = 0;
    double relMseStdError = 0;
};
PilotMeasurement measurePair(const image::Image& a, const image::Image& b, double secondsA,
                             double secondsB);
double efficiency(const PilotMeasurement& m);  // 1 / (seconds x relMSE)

// Relative standard deviation assumed for one pilot's render time.
inline constexpr double PILOT_TIME_NOISE = 0.03;

// Whether `candidate` is more efficient than `incumbent` by more than
// EVIDENCE_SIGMAS standard deviations of the log of their ratio (the error
// estimates' standard errors and PILOT_TIME_NOISE): a knob moves off its
// incumbent only on evidence. At two, a candidate no better than the
// incumbent wins one comparison in 40, and the search makes about six.
inline constexpr double EVIDENCE_SIGMAS = 2;
bool clearlyMoreEfficient(const PilotMeasurement& candidate, const PilotMeasurement& incumbent);
// The same for time alone (kernel form, paths in flight: the same image).
bool clearlyFaster(double candidateSeconds, double incumbentSeconds);

struct AutoRequest {
    // The render's settings: its film, depth, seed and the flags given; the
    // knobs not given hold their defaults.
    wavefront::RenderSettings base;
    // Knobs given as flags: fixed, left out of the search.
    bool givenRouletteDepth = false;
    bool givenLightSamples = false;
    bool givenSampler = false;
    bool givenGuideSpheres = false;
    bool givenKernel = false;
    bool givenPathsInFlight = false;
    bool givenLightSampler = false;
    bool sceneHasLights = false;        // light samples are drawn
    bool sceneHasLightTree = false;     // lights can be chosen through a tree (power or tree)
    bool lightTreeByDefault = false;    // base.lightSampling resolves to the tree
    bool sceneHasGuideSpheres = false;  // the guide fraction is used
    bool gpu = false;                   // the kernel form and paths in flight apply
    wavefront::KernelForm defaultForm = wavefront::KernelForm::Megakernel;  // the device's
    uint32_t defaultPathsInFlight = 1u << 20;                               // the device's
    // The render's budget: its sample cap (unset: none), time budget and
    // target error; at least one is set.
    std::optional<uint32_t> spp;
    std::optional<double> timeBudget;
    std::optional<double> targetError;
};

// Runs the pilots through `render` and returns the choice. The pilots' seeds
// are derived from base.seed but never equal it, so the choice is independent
// of the render's own random numbers and cannot bias it.
AutoChoice chooseSettings(const AutoRequest& request, const PilotRenderer& render);

}  // namespace vkpath::app
