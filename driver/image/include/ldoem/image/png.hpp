// PNG files written to memory, without time or text chunks, so that the same pixels always give
// the same bytes (the previews are compared byte for byte in tests).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/base/expected.hpp"

namespace ldoem::image {

enum class PngError : std::uint8_t {
  empty_image,    // a width or height of zero
  too_large,      // more than kMaxPngSide pixels on a side
  size_mismatch,  // the pixel count is not width x height (x channels)
  png_failed,     // libpng reported an error
};

[[nodiscard]] std::string_view to_string(PngError error);

// Larger sides are legal PNG but no preview needs them, and the limit keeps row buffers small.
inline constexpr std::uint32_t kMaxPngSide = 65535;

enum class GrayDepth : std::uint8_t { eight = 8, sixteen = 16 };

// Row-major samples; with GrayDepth::eight only the low byte of each sample is written.
struct GrayImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  GrayDepth depth = GrayDepth::sixteen;
  std::vector<std::uint16_t> pixels;
};

// The PNG file's bytes (colour type grey, 8 or 16 bits per sample).
[[nodiscard]] base::Expected<std::string, PngError> encode_gray_png(const GrayImage& image);

// Row-major 8-bit RGB, three bytes per pixel (renderings of a cloud).
struct RgbImage {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3
};

// The PNG file's bytes (colour type RGB, 8 bits per sample).
[[nodiscard]] base::Expected<std::string, PngError> encode_rgb_png(const RgbImage& image);

}  // namespace ldoem::image
