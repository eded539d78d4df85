#include "ldoem/image/png.hpp"
#include "png_writer.hpp"

#include <cstring>

namespace ldoem::image {
namespace {

void fill_rgb_row(const void* pixels, std::uint32_t row, png_byte* out) {
  const auto& image = *static_cast<const RgbImage*>(pixels);
  std::memcpy(out, image.pixels.data() + std::size_t{row} * image.width * 3, std::size_t{image.width} * 3);
}

}  // namespace

base::Expected<std::string, PngError> encode_rgb_png(const RgbImage& image) {
  const detail::PngLayout layout{image.width, image.height, 8, PNG_COLOR_TYPE_RGB, 3};
  return detail::encode_png(layout, image.pixels.size(), &image, fill_rgb_row);
}

}  // namespace ldoem::image
