// What `vkpath converge` measures and how it reads its flags, apart from the
// rendering: sample-count lists, the knob table of --sweep, and the figures
// taken from a convergence curve (time to reach an error, efficiency).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "wavefront/render_types.h"

namespace vkpath::app {

// "1,2,4,8": strictly increasing sample counts >= 1. Throws InputError.
std::vector<uint32_t> parseSppList(const std::string& text);

// One row of the knob table: a render setting --sweep can vary. Adding a knob
// is one row in KNOBS (convergence.cpp).
struct Knob {
    const char* name;
    const char* values;  // what the values look like, for error messages
    // Sets the knob in `settings`; throws InputError naming the knob when `value` is bad.
    void (*apply)(wavefront::RenderSettings& settings, const std::string& value);
    // Some values change the image's expectation (clamping removes energy, a
    // short max depth drops light): only a reference shows that bias.
    bool biased;
};
const std::vector<Knob>& knobs();

// `--sweep KNOB=v1,v2,...`: the knob and its values, each checked by
// applying it. Throws InputError for an unknown knob or a bad value.
struct Sweep {
    const Knob* knob = nullptr;
    std::vector<std::string> values;
};
Sweep parseSweep(const std::string& text);

// The error and cost of a render at one sample count.
struct Checkpoint {
    uint32_t spp = 0;
    double wallSeconds = 0;               // rendering so far, wall clock
    std::optional<double> deviceSeconds;  // GPU: summed stage timestamps; none on the CPU
    double relMse = 0;
    double rmse = 0;
    double relMseTrimmed = 0;    // image::ChannelMetrics::relMseTrimmed
    double estimatedRelMse = 0;  // the render's own estimate (wavefront/sample_schedule.h)
};

// The time at which the curve first reaches relMSE <= target, interpolated
// linearly in (log time, log relMSE) between the checkpoints around the
// crossing (error falls as a power of time, a line on log-log axes). The
// first checkpoint's time if it already reaches the target; nullopt if the
// curve never does.
std::optional<double> timeToRelMse(const std::vector<Checkpoint>& curve, double target);

// 1 / (wall seconds x relMSE) at the last checkpoint: a Monte Carlo
// estimator's efficiency 1 / (variance x time) (pbrt-v4, Section 2.1.4) with
// relMSE for the variance, so a setting that halves the error at equal time,
// or the time at equal error, doubles it.
// 0 for an empty curve; +inf for a zero error.
double efficiency(const std::vector<Checkpoint>& curve);

}  // namespace vkpath::app
