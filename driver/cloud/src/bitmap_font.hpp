// A 5x7 bitmap font of the project's own drawing, for the labels of the render (internal): the
// digits, A-Z, a-z and the punctuation the labels use; any other
// character is drawn as '?'. No font file is read, so the pictures need nothing installed.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "ldoem/image/png.hpp"

namespace ldoem::cloud::detail {

using Rgb = std::array<std::uint8_t, 3>;

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;

// Width in pixels of `text` drawn at `scale` (one blank column between characters).
int text_width(std::string_view text, int scale);

// Draws `text` with its top-left corner at (x, y); pixels outside the image are skipped.
void draw_text(image::RgbImage& picture, int x, int y, std::string_view text, Rgb colour, int scale);

// Fills the rectangle [x0, x1) x [y0, y1), clipped to the image.
void fill_rect(image::RgbImage& picture, int x0, int y0, int x1, int y1, Rgb colour);

// A one-pixel line from (x0, y0) to (x1, y1), clipped to the image.
void draw_line(image::RgbImage& picture, double x0, double y0, double x1, double y1, Rgb colour);

}  // namespace ldoem::cloud::detail
