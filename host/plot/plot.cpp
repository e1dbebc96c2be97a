#include "plot/plot.h"

#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <limits>
#include <memory>
#include <stdexcept>

namespace vkpath::plot {
namespace {

// Text: DejaVu Sans through fontconfig (Debian's fonts-dejavu-core), at this
// size in pixels; rows of text are LINE_HEIGHT apart.
constexpr const char* FONT = "DejaVu Sans";
constexpr double FONT_SIZE = 15;
constexpr int LINE_HEIGHT = 22;
constexpr int PANEL_WIDTH = 300;

// An sRGB colour, 0..255 per channel: what Cairo draws with and the PNG holds.
struct Srgb {
    int r, g, b;
};

// The palette and the chart's greys are sRGB values; the image is linear.
glm::vec3 linear(Srgb c) {
    auto channel = [](int v) {
        const double x = v / 255.0;
        return float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
    };
    return {channel(c.r), channel(c.g), channel(c.b)};
}

constexpr Srgb BLACK{0, 0, 0};
constexpr Srgb TEXT{30, 30, 30};
constexpr Srgb DECADE_GRID{200, 200, 200};
constexpr Srgb MINOR_GRID{235, 235, 235};

// Blue, vermillion, bluish green, reddish purple, orange, sky blue, black,
// yellow: the order puts the most distinct first; yellow, faint on white, last.
constexpr std::array<Srgb, 8> PALETTE = {Srgb{0, 114, 178}, {213, 94, 0},  {0, 158, 115},
                                         {204, 121, 167},   {230, 159, 0}, {86, 180, 233},
                                         {0, 0, 0},         {240, 228, 66}};

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

// A Cairo image surface on white, drawn on in pixel coordinates.
class Canvas {
  public:
    Canvas(uint32_t width, uint32_t height)
        : m_surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(width), int(height)),
                    &cairo_surface_destroy),
          m_cairo(cairo_create(m_surface.get()), &cairo_destroy) {
        if (cairo_surface_status(m_surface.get()) != CAIRO_STATUS_SUCCESS)
            throw std::runtime_error(fmt::format("cannot make a {}x{} chart", width, height));
        cairo_set_source_rgb(m_cairo.get(), 1, 1, 1);
        cairo_paint(m_cairo.get());
        cairo_select_font_face(m_cairo.get(), FONT, CAIRO_FONT_SLANT_NORMAL,
                               CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_font_size(m_cairo.get(), FONT_SIZE);
    }

    void color(Srgb c) {
        cairo_set_source_rgb(m_cairo.get(), c.r / 255.0, c.g / 255.0, c.b / 255.0);
    }

    void fillRect(double x0, double y0, double x1, double y1, Srgb c) {
        color(c);
        cairo_rectangle(m_cairo.get(), x0, y0, x1 - x0, y1 - y0);
        cairo_fill(m_cairo.get());
    }

    void line(glm::dvec2 a, glm::dvec2 b, double width, Srgb c) {
        color(c);
        cairo_set_line_width(m_cairo.get(), width);
        cairo_move_to(m_cairo.get(), a.x, a.y);
        cairo_line_to(m_cairo.get(), b.x, b.y);
        cairo_stroke(m_cairo.get());
    }

    // Circle, square, triangle, diamond, in turn per series.
    void marker(size_t kind, double cx, double cy, Srgb c) {
        constexpr double R = 5.5;
        cairo_t* cr = m_cairo.get();
        color(c);
        switch (kind % 4) {
            case 0:
                cairo_arc(cr, cx, cy, R, 0, 2 * M_PI);
                break;
            case 1:
                cairo_rectangle(cr, cx - 0.8 * R, cy - 0.8 * R, 1.6 * R, 1.6 * R);
                break;
            case 2:
                cairo_move_to(cr, cx, cy - R);
                cairo_line_to(cr, cx + R, cy + 0.7 * R);
                cairo_line_to(cr, cx - R, cy + 0.7 * R);
                cairo_close_path(cr);
                break;
            default:
                cairo_move_to(cr, cx, cy - 1.1 * R);
                cairo_line_to(cr, cx + 1.1 * R, cy);
                cairo_line_to(cr, cx, cy + 1.1 * R);
                cairo_line_to(cr, cx - 1.1 * R, cy);
                cairo_close_path(cr);
        }
        cairo_fill(cr);
    }

    double textWidth(const std::string& s) {
        cairo_text_extents_t e;
        cairo_text_extents(m_cairo.get(), s.c_str(), &e);
        return e.x_advance;
    }

    // `s` with its top-left corner at (x, y): the line's ascent below y.
    void text(double x, double y, const std::string& s, Srgb c = TEXT) {
        cairo_font_extents_t font;
        cairo_font_extents(m_cairo.get(), &font);
        color(c);
        cairo_move_to(m_cairo.get(), x, y + font.ascent);
        cairo_show_text(m_cairo.get(), s.c_str());
    }
    // The same turned a quarter anticlockwise, reading upwards, its top-left
    // corner (the start of the text) at (x, y).
    void verticalText(double x, double y, const std::string& s, Srgb c = TEXT) {
        cairo_save(m_cairo.get());
        cairo_translate(m_cairo.get(), x, y);
        cairo_rotate(m_cairo.get(), -M_PI / 2);
        text(0, 0, s, c);
        cairo_restore(m_cairo.get());
    }

    // The picture as linear RGB (Cairo's pixels are the sRGB values drawn).
    image::Image take() {
        cairo_surface_flush(m_surface.get());
        const int width = cairo_image_surface_get_width(m_surface.get());
        const int height = cairo_image_surface_get_height(m_surface.get());
        const int stride = cairo_image_surface_get_stride(m_surface.get());
        const unsigned char* data = cairo_image_surface_get_data(m_surface.get());
        image::Image picture{uint32_t(width), uint32_t(height)};
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                uint32_t p;  // CAIRO_FORMAT_RGB24: 0x00RRGGBB in a native-endian word
                std::memcpy(&p, data + size_t(y) * stride + size_t(x) * 4, 4);
                picture.at(uint32_t(x), uint32_t(y)) =
                    linear({int(p >> 16 & 255), int(p >> 8 & 255), int(p & 255)});
            }
        return picture;
    }

  private:
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> m_surface;
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> m_cairo;
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
    return linear(PALETTE[i % PALETTE.size()]);
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

    // ---- layout: title on top, the y label up the left, the legend panel on the right ----
    const double left = 20 + LINE_HEIGHT + canvas.textWidth("1e-10") + 10,
                 top = 20 + 2 * LINE_HEIGHT;
    const double right = double(chart.width) - PANEL_WIDTH - 20,
                 bottom = double(chart.height) - 2 * LINE_HEIGHT - 20;
    const LogAxis x{decadeRange(xMin, xMax), left, right};
    const LogAxis y{decadeRange(yMin, yMax), bottom, top};

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
        canvas.text(px - canvas.textWidth(label) / 2, bottom + 10, label);
    }
    for (int e = y.range.lo; e <= y.range.hi; ++e) {
        const double py = y.toPixel(std::pow(10.0, e));
        canvas.line({left, py}, {right, py}, 1, DECADE_GRID);
        canvas.line({left - 6.0, py}, {left, py}, 1.5, BLACK);
        const std::string label = decadeLabel(e);
        canvas.text(left - 10 - canvas.textWidth(label), py - LINE_HEIGHT / 2.0, label);
    }
    canvas.line({left, top}, {left, bottom}, 1.5, BLACK);
    canvas.line({left, bottom}, {right, bottom}, 1.5, BLACK);

    canvas.text(left, 12, chart.title);
    canvas.verticalText(16, (top + bottom + canvas.textWidth(chart.yLabel)) / 2, chart.yLabel);
    canvas.text((left + right - canvas.textWidth(chart.xLabel)) / 2, bottom + 14 + LINE_HEIGHT,
                chart.xLabel);

    // ---- the series: lines first, markers over them ------------------------------------
    for (size_t k = 0; k < chart.series.size(); ++k) {
        const Series& s = chart.series[k];
        const Srgb colour = PALETTE[k % PALETTE.size()];
        bool connected = false;  // a line from the previous point: not across a point left out
        glm::dvec2 previous(0.0);
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
            connected = connected && usable(s.x[i]) && usable(s.y[i]);
            if (!usable(s.x[i]) || !usable(s.y[i])) continue;
            const glm::dvec2 p(x.toPixel(s.x[i]), y.toPixel(s.y[i]));
            if (connected) canvas.line(previous, p, 2.5, colour);
            previous = p;
            connected = true;
        }
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (usable(s.x[i]) && usable(s.y[i]))
                canvas.marker(k, x.toPixel(s.x[i]), y.toPixel(s.y[i]), colour);
    }

    // ---- the legend: swatch and label, then the score as a bar --------------------------
    const double panel = double(chart.width) - PANEL_WIDTH;
    double row = top;
    const bool scored = !chart.scores.empty() && chart.scores.size() == chart.series.size();
    double best = 0;
    if (scored) {
        for (double v : chart.scores) best = std::max(best, std::isfinite(v) ? v : 0.0);
        canvas.text(panel, row - LINE_HEIGHT - 8, chart.scoreLabel);
    }
    for (size_t k = 0; k < chart.series.size(); ++k) {
        const Srgb colour = PALETTE[k % PALETTE.size()];
        const double cy = row + LINE_HEIGHT / 2.0;
        canvas.line({panel, cy}, {panel + 30.0, cy}, 2.5, colour);
        canvas.marker(k, panel + 15.0, cy, colour);
        canvas.text(panel + 40, row, chart.series[k].label);
        row += LINE_HEIGHT;
        if (scored) {
            const double v = std::isfinite(chart.scores[k]) ? chart.scores[k] : 0.0;
            constexpr double BAR = 90;
            const double length = best > 0 ? std::round(BAR * v / best) : 0;
            canvas.fillRect(panel + 40, row + 3, panel + 40 + std::max(length, 1.0),
                            row + LINE_HEIGHT - 5, colour);
            const bool mark = chart.series.size() > 1 && best > 0 && v == best;
            canvas.text(panel + 40 + BAR + 8, row, compactNumber(v) + (mark ? " best" : ""));
            row += LINE_HEIGHT;
        }
        row += 6;
    }
    return canvas.take();
}

}  // namespace vkpath::plot
