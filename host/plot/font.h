// A 5x7 bitmap font of our own design for chart labels: digits, ASCII
// letters and the punctuation numbers and settings need ("1e-3", "0.25 s",
// "max-depth=4", "1/(s x relMSE)"). Enough for plots that need nothing but
// host/image to be written.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string_view>

#include "image/image.h"

namespace vkpath::plot {

inline constexpr int GLYPH_WIDTH = 5;
inline constexpr int GLYPH_HEIGHT = 7;
inline constexpr int GLYPH_ADVANCE = 6;  // one column of space between glyphs
inline constexpr int GLYPH_DESCENT = 2;  // rows g, p, q, y reach below the baseline

// Rows top to bottom, bit 4 the leftmost column; nullptr for a character the
// font lacks (drawn as an empty box, so a missing glyph is visible).
const uint8_t* glyph(char c);
// Whether c's bitmap is drawn GLYPH_DESCENT rows lower (letters with descenders).
bool descending(char c);

// Width and height in pixels of `text` drawn at `scale` (pixels per font dot).
int textWidth(std::string_view text, int scale);
inline int textHeight(int scale) {
    return GLYPH_HEIGHT * scale;
}  // cap height; descenders reach below

// Draws `text` with its top-left corner at (x, y); pixels outside the image are skipped.
void drawText(image::Image& image, int x, int y, std::string_view text, glm::vec3 color, int scale);

}  // namespace vkpath::plot
