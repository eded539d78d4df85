// The libpng write sequence every PNG of this library shares; an encoder only says how its rows
// look. Kept in src/ so that a new colour type is one file of row filling in this folder.
#pragma once

#include <png.h>

#include <cstdint>
#include <string>

#include "ldoem/image/png.hpp"

namespace ldoem::image::detail {

struct PngLayout {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int bit_depth = 8;                  // bits per sample: 8 or 16
  int color_type = PNG_COLOR_TYPE_GRAY;
  std::uint32_t channels = 1;         // samples per pixel of color_type
};

// Fills one row of layout.width * channels samples, most significant byte first for 16 bits
// (PNG specification, section 7.1). Must not throw: it runs between libpng's setjmp and longjmp.
using RowFiller = void (*)(const void* pixels, std::uint32_t row, png_byte* out);

// Checks the layout (sides, sample count) and writes the PNG to memory.
[[nodiscard]] base::Expected<std::string, PngError> encode_png(const PngLayout& layout, std::size_t sample_count,
                                                                   const void* pixels, RowFiller fill_row);

}  // namespace ldoem::image::detail
