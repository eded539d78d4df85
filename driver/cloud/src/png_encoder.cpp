// Grayscale PNG through libpng, written to memory. libpng reports errors by longjmp, so the
// function that calls setjmp holds no object with a destructor and modifies no local after it.
#include <png.h>

#include <csetjmp>

#include "ldoem/cloud/range_image.hpp"

namespace ldoem::cloud {
namespace {

void append_png_bytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), length);
}

void flush_nothing(png_structp /*png*/) {}

// Quiet handlers: the caller gets png_failed, nothing is printed.
void fail_quietly(png_structp png, png_const_charp /*message*/) { png_longjmp(png, 1); }
void ignore_warning(png_structp /*png*/, png_const_charp /*message*/) {}

// PNG stores 16-bit samples most-significant byte first (PNG specification, section 7.1).
void fill_row(const RangeImage& image, std::uint32_t row, std::vector<png_byte>& buffer) {
  const std::uint16_t* pixels = image.pixels.data() + std::size_t{row} * image.width;
  for (std::uint32_t column = 0; column < image.width; ++column) {
    if (image.bit_depth == PngBitDepth::eight) {
      buffer[column] = static_cast<png_byte>(pixels[column]);
    } else {
      buffer[2 * column] = static_cast<png_byte>(pixels[column] >> 8);
      buffer[2 * column + 1] = static_cast<png_byte>(pixels[column] & 0xFF);
    }
  }
}

void write_rows(png_structp png, const RangeImage& image, std::vector<png_byte>& buffer) {
  for (std::uint32_t row = 0; row < image.height; ++row) {
    fill_row(image, row, buffer);
    png_write_row(png, buffer.data());
  }
}

bool write_png(png_structp png, png_infop info, const RangeImage& image, std::vector<png_byte>& buffer) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, image.width, image.height, static_cast<int>(image.bit_depth), PNG_COLOR_TYPE_GRAY,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  write_rows(png, image, buffer);
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

protocol::Expected<std::string, RangeImageError> encode_png(const RangeImage& image) {
  if (image.width == 0 || image.height == 0) return protocol::Unexpected(RangeImageError::empty_image);
  if (image.width > max_range_image_side || image.height > max_range_image_side) {
    return protocol::Unexpected(RangeImageError::too_large);
  }
  if (image.pixels.size() != std::size_t{image.width} * image.height) {
    return protocol::Unexpected(RangeImageError::empty_image);
  }
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, fail_quietly, ignore_warning);
  if (png == nullptr) return protocol::Unexpected(RangeImageError::png_failed);
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return protocol::Unexpected(RangeImageError::png_failed);
  }
  std::string bytes;
  std::vector<png_byte> row_buffer(std::size_t{image.width} * (image.bit_depth == PngBitDepth::eight ? 1 : 2));
  png_set_write_fn(png, &bytes, append_png_bytes, flush_nothing);
  const bool written = write_png(png, info, image, row_buffer);
  png_destroy_write_struct(&png, &info);
  if (!written) return protocol::Unexpected(RangeImageError::png_failed);
  return bytes;
}

}  // namespace ldoem::cloud
