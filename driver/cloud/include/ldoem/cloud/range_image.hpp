// Range-image preview of a scan: one row per layer, one column per beam, near = bright,
// no echo = black. Encoded as a grayscale PNG (8 or 16 bit) by driver/image, so the same cloud
// always gives the same bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/image/png.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::cloud {

enum class RangeImageError : std::uint8_t {
  no_image_layout,  // the cloud has neither image positions nor an organised layout
  empty_image,      // no points, or a width/height of zero
  too_large,        // more than max_range_image_side pixels on a side
  bad_range_scale,  // near/far not finite, negative, or far < near
  png_failed,       // libpng reported an error
  cannot_open_file,
  io_failed,
};

[[nodiscard]] std::string_view to_string(RangeImageError error);

inline constexpr std::uint32_t max_range_image_side = image::kMaxPngSide;

struct RangeImageOptions {
  image::GrayDepth bit_depth = image::GrayDepth::sixteen;
  // Ranges mapped to full and to minimal brightness; by default the nearest and the furthest
  // echo of the cloud. Ranges beyond are clamped (an echo never becomes black).
  std::optional<double> near_m;
  std::optional<double> far_m;
  Point3f origin;  // the ranges are measured from here (the scanner's optical centre)
  bool last_layer_on_top = false;  // false: image row r is layer r
};

// Positions come from the image_position channel (size = max row/column + 1), else from the
// organised layout; several points on one pixel keep the nearest; NaN points are no echo.
// Pixels are row-major, 0 = no echo, 1..max = far..near (max 255 or 65535).
[[nodiscard]] base::Expected<image::GrayImage, RangeImageError> make_range_image(
    const PointCloud& cloud, const RangeImageOptions& options = {});

// make_range_image + image::encode_gray_png: the PNG file's bytes.
[[nodiscard]] base::Expected<std::string, RangeImageError> encode_range_image_png(
    const PointCloud& cloud, const RangeImageOptions& options = {});

// encode_range_image_png + write; returns the number of bytes written.
[[nodiscard]] base::Expected<std::size_t, RangeImageError> write_range_image_png(
    const std::filesystem::path& path, const PointCloud& cloud, const RangeImageOptions& options = {});

}  // namespace ldoem::cloud
