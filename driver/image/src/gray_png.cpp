#include "ldoem/image/png.hpp"
#include "png_writer.hpp"

namespace ldoem::image {
namespace {

void fill_gray_row(const void* pixels, std::uint32_t row, png_byte* out) {
  const auto& image = *static_cast<const GrayImage*>(pixels);
  const std::uint16_t* samples = image.pixels.data() + std::size_t{row} * image.width;
  for (std::uint32_t column = 0; column < image.width; ++column) {
    if (image.depth == GrayDepth::eight) {
      out[column] = static_cast<png_byte>(samples[column]);
    } else {
      out[2 * column] = static_cast<png_byte>(samples[column] >> 8);
      out[2 * column + 1] = static_cast<png_byte>(samples[column] & 0xFF);
    }
  }
}

}  // namespace

std::string_view to_string(PngError error) {
  switch (error) {
    case PngError::empty_image: return "empty_image";
    case PngError::too_large: return "too_large";
    case PngError::size_mismatch: return "size_mismatch";
    case PngError::png_failed: return "png_failed";
  }
  return "unknown";
}

base::Expected<std::string, PngError> encode_gray_png(const GrayImage& image) {
  const detail::PngLayout layout{image.width, image.height, static_cast<int>(image.depth), PNG_COLOR_TYPE_GRAY, 1};
  return detail::encode_png(layout, image.pixels.size(), &image, fill_gray_row);
}

}  // namespace ldoem::image
