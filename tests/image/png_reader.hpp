// What libpng reads back from PNG bytes: the tests' independent check of the encoders.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ldoem::image::testing {

struct DecodedPng {
  bool ok = false;  // false: not a PNG, or libpng reported an error
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int bit_depth = 0;
  int color_type = -1;
  int channels = 0;
  std::vector<std::uint16_t> samples;  // row-major, `channels` samples per pixel
};

DecodedPng decode_png(const std::string& bytes);

}  // namespace ldoem::image::testing
