// Log-log line charts rendered into an image::Image, for convergence plots
// (error against time): decade ticks with labels, faint grid lines at 2..9 x
// 10^k, one coloured line with markers per series, and a legend panel that
// can carry one score per series as a bar (the best one marked). Drawn by
// Cairo, anti-aliased, with its text in DejaVu Sans.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "image/image.h"

namespace vkpath::plot {

// The whole decades [10^lo, 10^hi] that cover [min, max] (both > 0), at
// least one decade wide, so every axis has at least two labelled ticks.
struct DecadeRange {
    int lo = 0;
    int hi = 1;
};
DecadeRange decadeRange(double min, double max);

// A decade's label as people write it: 0.01, 0.1, 1, 10, 100, then 1e-3, 1e3 beyond.
std::string decadeLabel(int exponent);

// A logarithmic axis: [10^lo, 10^hi] onto pixels [p0, p1] (p1 < p0 for a y axis that goes up).
struct LogAxis {
    DecadeRange range;
    double p0 = 0, p1 = 1;
    double toPixel(double value) const;
    // The minor ticks inside the range: 2..9 x 10^k.
    std::vector<double> minorTicks() const;
};

struct Series {
    std::string label;
    std::vector<double> x,
        y;  // points that are not finite and > 0 are left out (the line breaks there)
};

struct Chart {
    std::string title;
    std::string xLabel;
    std::string yLabel;
    std::vector<Series> series;
    // Optional, one per series: a figure of merit drawn as a bar in the
    // legend (proportional to the largest), the largest marked "best".
    std::vector<double> scores;
    std::string scoreLabel;
    uint32_t width = 1000;
    uint32_t height = 600;
};

// The colour of series i: the Okabe-Ito palette (Okabe and Ito 2008, "Color
// Universal Design"), told apart by the common kinds of colour blindness;
// markers change shape too, so series stay distinct past eight.
glm::vec3 seriesColor(size_t i);

// Linear RGB, for image::writePng.
image::Image renderChart(const Chart& chart);

}  // namespace vkpath::plot
