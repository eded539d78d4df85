// libpng reports errors by longjmp, so the function that calls setjmp holds no object with a
// destructor and modifies no local after it.
#include "png_writer.hpp"

#include <csetjmp>
#include <vector>

namespace ldoem::image::detail {
namespace {

void append_png_bytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), length);
}

void flush_nothing(png_structp /*png*/) {}

// Quiet handlers: the caller gets png_failed, nothing is printed.
void fail_quietly(png_structp png, png_const_charp /*message*/) { png_longjmp(png, 1); }
void ignore_warning(png_structp /*png*/, png_const_charp /*message*/) {}

struct RowSource {
  const void* pixels;
  RowFiller fill_row;
  png_byte* buffer;
};

bool write_png(png_structp png, png_infop info, const PngLayout& layout, const RowSource& rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_IHDR(png, info, layout.width, layout.height, layout.bit_depth, layout.color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (std::uint32_t row = 0; row < layout.height; ++row) {
    rows.fill_row(rows.pixels, row, rows.buffer);
    png_write_row(png, rows.buffer);
  }
  png_write_end(png, nullptr);
  return true;
}

}  // namespace

base::Expected<std::string, PngError> encode_png(const PngLayout& layout, std::size_t sample_count,
                                                     const void* pixels, RowFiller fill_row) {
  using base::Unexpected;
  if (layout.width == 0 || layout.height == 0) return Unexpected(PngError::empty_image);
  if (layout.width > kMaxPngSide || layout.height > kMaxPngSide) return Unexpected(PngError::too_large);
  const std::size_t samples_per_row = std::size_t{layout.width} * layout.channels;
  if (sample_count != samples_per_row * layout.height) return Unexpected(PngError::size_mismatch);

  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, fail_quietly, ignore_warning);
  if (png == nullptr) return Unexpected(PngError::png_failed);
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return Unexpected(PngError::png_failed);
  }
  std::string bytes;
  std::vector<png_byte> row_buffer(samples_per_row * (layout.bit_depth == 16 ? 2 : 1));
  png_set_write_fn(png, &bytes, append_png_bytes, flush_nothing);
  const bool written = write_png(png, info, layout, RowSource{pixels, fill_row, row_buffer.data()});
  png_destroy_write_struct(&png, &info);
  if (!written) return Unexpected(PngError::png_failed);
  return bytes;
}

}  // namespace ldoem::image::detail
