// The log-log chart's axis logic and what a rendered chart holds.
#include "plot/plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace {

using namespace vkpath;

TEST(PlotAxis, DecadeRangeCoversTheDataInWholeDecades) {
    EXPECT_EQ(plot::decadeRange(0.3, 0.8).lo, -1);
    EXPECT_EQ(plot::decadeRange(0.3, 0.8).hi, 0);
    EXPECT_EQ(plot::decadeRange(0.002, 45).lo, -3);
    EXPECT_EQ(plot::decadeRange(0.002, 45).hi, 2);
    // Exact powers of ten are their own bounds...
    EXPECT_EQ(plot::decadeRange(10, 100).lo, 1);
    EXPECT_EQ(plot::decadeRange(10, 100).hi, 2);
    // ...and a single value still gets a whole decade (two labelled ticks).
    EXPECT_EQ(plot::decadeRange(1e-3, 1e-3).lo, -3);
    EXPECT_EQ(plot::decadeRange(1e-3, 1e-3).hi, -2);
}

TEST(PlotAxis, DecadeLabelsReadAsPeopleWriteThem) {
    const std::vector<std::pair<int, std::string>> expected = {
        {-4, "1e-4"}, {-3, "1e-3"}, {-2, "0.01"}, {-1, "0.1"},
        {0, "1"},     {1, "10"},    {2, "100"},   {3, "1e3"}};
    for (const auto& [exponent, label] : expected)
        EXPECT_EQ(plot::decadeLabel(exponent), label) << exponent;
}

TEST(PlotAxis, DecadesAreEvenlySpacedAndMinorTicksFallBetween) {
    const plot::LogAxis x{{-1, 1}, 100, 300};
    EXPECT_DOUBLE_EQ(x.toPixel(0.1), 100);
    EXPECT_DOUBLE_EQ(x.toPixel(1), 200);
    EXPECT_DOUBLE_EQ(x.toPixel(10), 300);
    EXPECT_NEAR(x.toPixel(std::sqrt(10.0)), 250, 1e-9);
    const plot::LogAxis y{{-3, 0}, 500, 50};  // up the image
    EXPECT_DOUBLE_EQ(y.toPixel(1e-3), 500);
    EXPECT_DOUBLE_EQ(y.toPixel(1), 50);
    const auto ticks = x.minorTicks();
    ASSERT_EQ(ticks.size(), 16u);  // 2..9 in each of two decades
    EXPECT_DOUBLE_EQ(ticks.front(), 0.2);
    EXPECT_DOUBLE_EQ(ticks.back(), 9);
    for (double t : ticks) {
        EXPECT_GT(x.toPixel(t), 100);
        EXPECT_LT(x.toPixel(t), 300);
    }
}

int countColor(const image::Image& image, glm::vec3 color) {
    int n = 0;
    for (const glm::vec3& p : image.pixels)
        n += glm::all(glm::lessThan(glm::abs(p - color), glm::vec3(1e-6f)));
    return n;
}

TEST(PlotChart, DrawsEachSeriesInItsColourAtTheRequestedSize) {
    plot::Chart chart;
    chart.title = "test";
    chart.xLabel = "wall time (s)";
    chart.yLabel = "relMSE";
    chart.series = {{"a", {0.1, 1, 10}, {1, 0.1, 0.01}}, {"b", {0.2, 2, 20}, {0.5, 0.05, 0.04}}};
    chart.scores = {1, 2};
    chart.width = 800;
    chart.height = 500;
    const image::Image image = plot::renderChart(chart);
    EXPECT_EQ(image.width, 800u);
    EXPECT_EQ(image.height, 500u);
    // Lines, markers and legend in full colour: many pixels each.
    EXPECT_GT(countColor(image, plot::seriesColor(0)), 200);
    EXPECT_GT(countColor(image, plot::seriesColor(1)), 200);
    EXPECT_EQ(countColor(image, plot::seriesColor(2)), 0);
}

// Dark pixels (text, axes, ticks) in the rectangle [x0, x1) x [y0, y1).
int darkPixels(const image::Image& image, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) {
    int n = 0;
    for (uint32_t y = y0; y < y1; ++y)
        for (uint32_t x = x0; x < x1; ++x) n += image.at(x, y).y < 0.2f;
    return n;
}

// The title is text in a real font: drawn where it belongs, and a longer
// title covers more of the row than a shorter one.
TEST(PlotChart, TextIsDrawnWhereItBelongs) {
    plot::Chart chart;
    chart.series = {{"a", {0.1, 1}, {1, 0.1}}};
    chart.title = "";
    const image::Image untitled = plot::renderChart(chart);
    chart.title = "relMSE against wall time";
    const image::Image titled = plot::renderChart(chart);
    chart.title += ", and more words after it";
    const image::Image longer = plot::renderChart(chart);
    const uint32_t right = chart.width - 320;  // left of the legend panel
    EXPECT_EQ(darkPixels(untitled, 0, 0, right, 32), 0);
    const int ink = darkPixels(titled, 0, 0, right, 32);
    EXPECT_GT(ink, 150);
    EXPECT_GT(darkPixels(longer, 0, 0, right, 32), ink * 3 / 2);
}

TEST(PlotChart, PointsThatCannotGoOnLogAxesAreLeftOut) {
    plot::Chart chart;
    chart.series = {{"zero and nan", {0, 1, NAN}, {1, 0, 1}}};
    const image::Image image = plot::renderChart(chart);
    EXPECT_EQ(image.width, chart.width);
    // Only the legend's swatch carries the colour: no point was usable.
    const int legendOnly = countColor(image, plot::seriesColor(0));
    chart.series[0] = {"usable", {1, 10}, {1, 0.1}};
    EXPECT_GT(countColor(plot::renderChart(chart), plot::seriesColor(0)), legendOnly + 100);
}

}  // namespace
