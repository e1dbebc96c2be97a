#include "plot/plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <glm/glm.hpp>
#include <limits>

#include "plot/font.h"

namespace vkpath::plot {
namespace {

constexpr int FONT_SCALE = 2;
constexpr int LINE_HEIGHT = (GLYPH_HEIGHT + GLYPH_DESCENT) * FONT_SCALE + 4;
constexpr int PANEL_WIDTH = 300;

// The palette and the chart's greys are sRGB values; the image is linear.
glm::vec3 srgb(int r, int g, int b) {
    auto linear = [](int v) {
        const double c = v / 255.0;
        return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    };
    return {linear(r), linear(g), linear(b)};
}

const glm::vec3 BLACK = srgb(0, 0, 0);
const glm::vec3 TEXT = srgb(30, 30, 30);
const glm::vec3 DECADE_GRID = srgb(200, 200, 200);
const glm::vec3 MINOR_GRID = srgb(235, 235, 235);

bool usable(double v) {
    return std::isfinite(v) && v > 0;
}

// Three significant digits, exponents without '+' and leading zeros (2.41e4),
// so a legend figure stays short.
std::string compactNumber(double v) {
    if (!std::isfinite(v)) return v > 0 ? "inf" : "-";
    if (v == 0 || (std::abs(v) >= 0.01 && std::abs(v) < 1e4)) return fmt::format("{:.3g}", v);
    const int exponent = int(std::floor(std::log10(std::abs(v))));
    return fmt::format("{:.3g}e{}", v / std::pow(10.0, exponent), exponent);
}

class Canvas {
  public:
    explicit Canvas(uint32_t width, uint32_t height) : m_image(width, height) {
        std::fill(m_image.pixels.begin(), m_image.pixels.end(), glm::vec3(1.0f));
    }

    void blend(int x, int y, glm::vec3 color, float alpha) {
        if (x < 0 || y < 0 || x >= int(m_image.width) || y >= int(m_image.height) || alpha <= 0)
            return;
        glm::vec3& p = m_image.at(uint32_t(x), uint32_t(y));
        p = glm::mix(p, color, std::min(alpha, 1.0f));
    }

    void fillRect(int x0, int y0, int x1, int y1, glm::vec3 color) {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) blend(x, y, color, 1.0f);
    }

    // A segment `width` pixels wide, anti-aliased by each pixel's distance to it.
    void line(glm::dvec2 a, glm::dvec2 b, double width, glm::vec3 color) {
        const double reach = width / 2 + 1;
        const int x0 = int(std::floor(std::min(a.x, b.x) - reach)),
                  x1 = int(std::ceil(std::max(a.x, b.x) + reach));
        const int y0 = int(std::floor(std::min(a.y, b.y) - reach)),
                  y1 = int(std::ceil(std::max(a.y, b.y) + reach));
        const glm::dvec2 ab = b - a;
        const double length2 = glm::dot(ab, ab);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const glm::dvec2 p(x + 0.5, y + 0.5);
                const double t =
                    length2 > 0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
                const double d = glm::length(p - (a + t * ab));
                blend(x, y, color, float(std::clamp(width / 2 + 0.5 - d, 0.0, 1.0)));
            }
    }

    // A filled shape given by an inside test around (cx, cy), 4x4 samples per pixel.
    void shape(double cx, double cy, double radius, glm::vec3 color,
               const std::function<bool(double, double)>& inside) {
        for (int y = int(cy - radius) - 1; y <= int(cy + radius) + 1; ++y)
            for (int x = int(cx - radius) - 1; x <= int(cx + radius) + 1; ++x) {
                int hits = 0;
                for (int sy = 0; sy < 4; ++sy)
                    for (int sx = 0; sx < 4; ++sx)
                        hits += inside((x + (sx + 0.5) / 4 - cx) / radius,
                                       (y + (sy + 0.5) / 4 - cy) / radius);
                blend(x, y, color, hits / 16.0f);
            }
    }

    // Circle, square, triangle, diamond, in turn per series.
    void marker(size_t kind, double cx, double cy, glm::vec3 color) {
        static const std::array<std::function<bool(double, double)>, 4> shapes = {
            [](double u, double v) { return u * u + v * v <= 1; },
            [](double u, double v) { return std::abs(u) <= 0.8 && std::abs(v) <= 0.8; },
            [](double u, double v) { return v <= 0.7 && v >= -1 + 2 * std::abs(u) * 0.97; },
            [](double u, double v) { return std::abs(u) + std::abs(v) <= 1.1; }};
        shape(cx, cy, 5.5, color, shapes[kind % shapes.size()]);
    }

    void text(int x, int y, const std::string& s, glm::vec3 color = TEXT) {
        drawText(m_image, x, y, s, color, FONT_SCALE);
    }

    image::Image take() { return std::move(m_image); }

  private:
    image::Image m_image;
};

}  // namespace

DecadeRange decadeRange(double min, double max) {
    DecadeRange r{int(std::floor(std::log10(min))), int(std::ceil(std::log10(max)))};
    if (r.hi <= r.lo) r.hi = r.lo + 1;
    return r;
}

std::string decadeLabel(int exponent) {
    if (exponent >= 0 && exponent <= 2)
        return fmt::format("{}", int(std::lround(std::pow(10.0, exponent))));
    if (exponent < 0 && exponent >= -2) return "0." + std::string(size_t(-exponent - 1), '0') + "1";
    return fmt::format("1e{}", exponent);
}

double LogAxis::toPixel(double value) const {
    const double t = (std::log10(value) - range.lo) / double(range.hi - range.lo);
    return p0 + t * (p1 - p0);
}

std::vector<double> LogAxis::minorTicks() const {
    std::vector<double> ticks;
    for (int e = range.lo; e < range.hi; ++e)
        for (int m = 2; m <= 9; ++m) ticks.push_back(m * std::pow(10.0, e));
    return ticks;
}

glm::vec3 seriesColor(size_t i) {
    // Blue, vermillion, bluish green, reddish purple, orange, sky blue, black,
    // yellow: the order puts the most distinct first; yellow, faint on white, last.
    static const std::array<glm::vec3, 8> palette = {
        srgb(0, 114, 178), srgb(213, 94, 0),   srgb(0, 158, 115), srgb(204, 121, 167),
        srgb(230, 159, 0), srgb(86, 180, 233), srgb(0, 0, 0),     srgb(240, 228, 66)};
    return palette[i % palette.size()];
}

image::Image renderChart(const Chart& chart) {
    Canvas canvas(chart.width, chart.height);

    // ---- ranges: whole decades around every usable point ----------------------------
    double xMin = std::numeric_limits<double>::infinity(), xMax = 0, yMin = xMin, yMax = 0;
    for (const Series& s : chart.series)
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (usable(s.x[i]) && usable(s.y[i])) {
                xMin = std::min(xMin, s.x[i]), xMax = std::max(xMax, s.x[i]);
                yMin = std::min(yMin, s.y[i]), yMax = std::max(yMax, s.y[i]);
            }
    if (xMax == 0) xMin = xMax = yMin = yMax = 1;  // nothing to draw: empty axes from 1 to 10

    // ---- layout: title on top, the legend panel on the right --------------------------
    const int left = 20 + textWidth("1e-10", FONT_SCALE) + 10, top = 30 + 2 * LINE_HEIGHT;
    const int right = int(chart.width) - PANEL_WIDTH - 20,
              bottom = int(chart.height) - 2 * LINE_HEIGHT - 20;
    const LogAxis x{decadeRange(xMin, xMax), double(left), double(right)};
    const LogAxis y{decadeRange(yMin, yMax), double(bottom), double(top)};

    // ---- grid, ticks and their labels ----------------------------------------------------
    for (double v : x.minorTicks())
        canvas.line({x.toPixel(v), top}, {x.toPixel(v), bottom}, 1, MINOR_GRID);
    for (double v : y.minorTicks())
        canvas.line({left, y.toPixel(v)}, {right, y.toPixel(v)}, 1, MINOR_GRID);
    for (int e = x.range.lo; e <= x.range.hi; ++e) {
        const double px = x.toPixel(std::pow(10.0, e));
        canvas.line({px, top}, {px, bottom}, 1, DECADE_GRID);
        canvas.line({px, bottom}, {px, bottom + 6.0}, 1.5, BLACK);
        const std::string label = decadeLabel(e);
        canvas.text(int(px) - textWidth(label, FONT_SCALE) / 2, bottom + 12, label);
    }
    for (int e = y.range.lo; e <= y.range.hi; ++e) {
        const double py = y.toPixel(std::pow(10.0, e));
        canvas.line({left, py}, {right, py}, 1, DECADE_GRID);
        canvas.line({left - 6.0, py}, {left, py}, 1.5, BLACK);
        const std::string label = decadeLabel(e);
        canvas.text(left - 10 - textWidth(label, FONT_SCALE), int(py) - textHeight(FONT_SCALE) / 2,
                    label);
    }
    canvas.line({left, top}, {left, bottom}, 1.5, BLACK);
    canvas.line({left, bottom}, {right, bottom}, 1.5, BLACK);

    canvas.text(left, 12, chart.title);
    canvas.text(left - textWidth("1e-10", FONT_SCALE) / 2, top - LINE_HEIGHT - 8, chart.yLabel);
    canvas.text((left + right - textWidth(chart.xLabel, FONT_SCALE)) / 2, bottom + 14 + LINE_HEIGHT,
                chart.xLabel);

    // ---- the series: lines first, markers over them ------------------------------------
    for (size_t k = 0; k < chart.series.size(); ++k) {
        const Series& s = chart.series[k];
        bool connected = false;  // a line from the previous point: not across a point left out
        glm::dvec2 previous(0.0);
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            connected = connected && usable(s.x[i]) && usable(s.y[i]);
            if (!usable(s.x[i]) || !usable(s.y[i])) continue;
            const glm::dvec2 p(x.toPixel(s.x[i]), y.toPixel(s.y[i]));
            if (connected) canvas.line(previous, p, 2.5, seriesColor(k));
            previous = p;
            connected = true;
        }
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (usable(s.x[i]) && usable(s.y[i]))
                canvas.marker(k, x.toPixel(s.x[i]), y.toPixel(s.y[i]), seriesColor(k));
    }

    // ---- the legend: swatch and label, then the score as a bar --------------------------
    const int panel = int(chart.width) - PANEL_WIDTH;
    int row = top;
    const bool scored = !chart.scores.empty() && chart.scores.size() == chart.series.size();
    double best = 0;
    if (scored) {
        for (double v : chart.scores) best = std::max(best, std::isfinite(v) ? v : 0.0);
        canvas.text(panel, row - LINE_HEIGHT - 8, chart.scoreLabel);
    }
    for (size_t k = 0; k < chart.series.size(); ++k) {
        const double cy = row + textHeight(FONT_SCALE) / 2.0;
        canvas.line({panel, cy}, {panel + 30.0, cy}, 2.5, seriesColor(k));
        canvas.marker(k, panel + 15.0, cy, seriesColor(k));
        canvas.text(panel + 40, row, chart.series[k].label);
        row += LINE_HEIGHT;
        if (scored) {
            const double v = std::isfinite(chart.scores[k]) ? chart.scores[k] : 0.0;
            constexpr int BAR = 90;
            const int length = best > 0 ? int(std::lround(BAR * v / best)) : 0;
            canvas.fillRect(panel + 40, row, panel + 40 + std::max(length, 1),
                            row + textHeight(FONT_SCALE), seriesColor(k));
            const bool mark = chart.series.size() > 1 && best > 0 && v == best;
            canvas.text(panel + 40 + BAR + 8, row, compactNumber(v) + (mark ? " best" : ""));
            row += LINE_HEIGHT;
        }
        row += 6;
    }
    return canvas.take();
}

}  // namespace vkpath::plot
