// What `vkpath render --auto` chose (app/auto_search.h makes the choice):
// the value of each knob that changes how fast an image converges and never
// what it converges to, how each was reached, and what the pilots cost. The
// choice is printed as one line, written into the EXR (`vkpath:auto`) and
// kept in the checkpoint, so that a resumed render goes on with it instead
// of choosing again.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "app/render_options.h"

namespace vkpath::app {

// How a knob's value was reached.
enum class KnobSource {
    Measured,      // the pilots compared its candidates
    Given,         // an explicit flag: excluded from the search
    NotMeasured,   // the budget ran out before its turn: the default kept
    DoesNotApply,  // nothing in this scene or render that it changes
};
const char* knobSourceName(KnobSource source);

struct AutoChoice {
    uint32_t rouletteDepth = 5;
    uint32_t lightSamples = 1;
    std::string sampler = "sobol";
    float guideSpheres = 0.25f;
    std::string lightSampler = "auto";  // --light-sampler's names
    std::string kernel;                 // GPU: "megakernel" or "wavefront"; empty for --device cpu
    uint32_t pathsInFlight = 0;         // GPU: the most paths of a wave; 0 for --device cpu
    // Per knob ("rr-depth", "light-samples", "sampler", "light-sampler",
    // "guide-spheres", "kernel", "paths-in-flight"), in that order.
    std::vector<std::pair<std::string, KnobSource>> sources;
    // What the pilots cost: their render time (the part held to 5% of the
    // budget), building their renderers (scene upload, pipeline creation;
    // counted apart, it is paid once per kernel specialisation and cached)
    // and the render's budget itself (seconds).
    double pilotSeconds = 0;
    double setupSeconds = 0;
    double budgetSeconds = 0;
    uint32_t pilotRenders = 0;
    std::string pilotFilm;  // "WxH at N spp", the size the variance knobs were compared at
    // Set when the search stopped before comparing anything: why.
    std::string skipped;
    bool resumed = false;  // read from a checkpoint, not measured by this run
};

// The one line that `render --auto` prints, e.g. "auto: rr-depth 5, light
// samples 2, sampler sobol, guide 0.25, kernel megakernel, paths 2^20
// (pilots 0.21 s, 4.1% of the budget 5.1 s; ...)".
std::string describeAutoChoice(const AutoChoice& choice);

// The choice as a JSON object (the EXR's vkpath:auto, the checkpoint's
// "auto"), and back; parseAutoChoice throws InputError naming `what` for
// text that is not one.
std::string autoChoiceJson(const AutoChoice& choice);
AutoChoice parseAutoChoice(const std::string& json, const std::string& what);

// The options with the choice's values in place of their own.
void applyAutoChoice(const AutoChoice& choice, RenderOptions& options);

}  // namespace vkpath::app
