// libpng reports errors by longjmp: the function that calls setjmp holds no object with a
// destructor.
#include "png_reader.hpp"

#include <png.h>

#include <csetjmp>
#include <cstring>

namespace ldoem::image::testing {
namespace {

struct MemoryReader {
  const std::string* bytes;
  std::size_t offset;
};

void read_from_memory(png_structp png, png_bytep out, png_size_t length) {
  auto* reader = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (reader->offset + length > reader->bytes->size()) png_error(png, "read past end");
  std::memcpy(out, reader->bytes->data() + reader->offset, length);
  reader->offset += length;
}

void read_rows(png_structp png, png_infop info, DecodedPng& decoded, std::vector<png_byte>& row) {
  png_read_info(png, info);
  decoded.width = png_get_image_width(png, info);
  decoded.height = png_get_image_height(png, info);
  decoded.bit_depth = png_get_bit_depth(png, info);
  decoded.color_type = png_get_color_type(png, info);
  decoded.channels = png_get_channels(png, info);
  row.resize(png_get_rowbytes(png, info));
  const std::size_t samples_per_row = std::size_t{decoded.width} * static_cast<std::size_t>(decoded.channels);
  for (png_uint_32 y = 0; y < decoded.height; ++y) {
    png_read_row(png, row.data(), nullptr);
    for (std::size_t x = 0; x < samples_per_row; ++x) {
      decoded.samples.push_back(decoded.bit_depth == 16 ? static_cast<std::uint16_t>((row[2 * x] << 8) | row[2 * x + 1])
                                                        : row[x]);
    }
  }
  png_read_end(png, nullptr);
  decoded.ok = true;
}

bool read_guarded(png_structp png, png_infop info, DecodedPng& decoded, std::vector<png_byte>& row) {
  if (setjmp(png_jmpbuf(png))) return false;
  read_rows(png, info, decoded, row);
  return true;
}

void fail_quietly(png_structp png, png_const_charp /*message*/) { png_longjmp(png, 1); }
void ignore_warning(png_structp /*png*/, png_const_charp /*message*/) {}

}  // namespace

DecodedPng decode_png(const std::string& bytes) {
  DecodedPng decoded;
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0) return decoded;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, fail_quietly, ignore_warning);
  png_infop info = png_create_info_struct(png);
  MemoryReader reader{&bytes, 0};
  std::vector<png_byte> row;
  png_set_read_fn(png, &reader, read_from_memory);
  if (!read_guarded(png, info, decoded, row)) decoded.ok = false;
  png_destroy_read_struct(&png, &info, nullptr);
  return decoded;
}

}  // namespace ldoem::image::testing
