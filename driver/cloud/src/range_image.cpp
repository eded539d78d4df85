#include "ldoem/cloud/range_image.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ldoem/cloud/cloud_file.hpp"

namespace ldoem::cloud {
namespace {

using base::Expected;
using base::Unexpected;

struct PixelIndex {
  std::uint32_t row;
  std::uint32_t column;
};

Expected<OrganisedSize, RangeImageError> image_size(const PointCloud& cloud) {
  if (cloud.channels().image_position) {
    OrganisedSize size;
    for (const ImagePosition& position : cloud.image_positions()) {
      if (position.row_layer >= max_range_image_side || position.column_beam >= max_range_image_side) {
        return Unexpected(RangeImageError::too_large);
      }
      size.height = std::max(size.height, position.row_layer + 1);
      size.width = std::max(size.width, position.column_beam + 1);
    }
    return size;
  }
  if (const std::optional<OrganisedSize> organised = cloud.organised()) {
    if (organised->width > max_range_image_side || organised->height > max_range_image_side) {
      return Unexpected(RangeImageError::too_large);
    }
    return *organised;
  }
  return Unexpected(RangeImageError::no_image_layout);
}

PixelIndex pixel_of(const PointCloud& cloud, std::size_t index) {
  if (cloud.channels().image_position) {
    const ImagePosition& position = cloud.image_positions()[index];
    return PixelIndex{position.row_layer, position.column_beam};
  }
  const std::uint32_t width = cloud.layout().width;
  return PixelIndex{static_cast<std::uint32_t>(index / width), static_cast<std::uint32_t>(index % width)};
}

// Range of each point from the origin, NaN when the point has no finite position.
std::vector<double> ranges_of(const PointCloud& cloud, const Point3f& origin) {
  std::vector<double> ranges;
  ranges.reserve(cloud.size());
  for (const Point3f& point : cloud.positions()) {
    const double range = std::sqrt(std::pow(double{point.x_m} - origin.x_m, 2) + std::pow(double{point.y_m} - origin.y_m, 2) +
                                   std::pow(double{point.z_m} - origin.z_m, 2));
    ranges.push_back(std::isfinite(range) ? range : std::numeric_limits<double>::quiet_NaN());
  }
  return ranges;
}

RangeImageError from_png_error(image::PngError error) {
  switch (error) {
    case image::PngError::too_large: return RangeImageError::too_large;
    case image::PngError::png_failed: return RangeImageError::png_failed;
    case image::PngError::empty_image:
    case image::PngError::size_mismatch: break;
  }
  return RangeImageError::empty_image;
}

}  // namespace

std::string_view to_string(RangeImageError error) {
  switch (error) {
    case RangeImageError::no_image_layout: return "no_image_layout";
    case RangeImageError::empty_image: return "empty_image";
    case RangeImageError::too_large: return "too_large";
    case RangeImageError::bad_range_scale: return "bad_range_scale";
    case RangeImageError::png_failed: return "png_failed";
    case RangeImageError::cannot_open_file: return "cannot_open_file";
    case RangeImageError::io_failed: return "io_failed";
  }
  return "unknown";
}

Expected<image::GrayImage, RangeImageError> make_range_image(const PointCloud& cloud, const RangeImageOptions& options) {
  if (cloud.empty()) return Unexpected(RangeImageError::empty_image);
  const Expected<OrganisedSize, RangeImageError> size = image_size(cloud);
  if (!size) return Unexpected(size.error());

  const std::vector<double> ranges = ranges_of(cloud, options.origin);
  double nearest = std::numeric_limits<double>::infinity();
  double furthest = 0.0;
  for (double range : ranges) {
    if (std::isnan(range)) continue;
    nearest = std::min(nearest, range);
    furthest = std::max(furthest, range);
  }
  const double near_m = options.near_m.value_or(std::isfinite(nearest) ? nearest : 0.0);
  const double far_m = options.far_m.value_or(std::isfinite(nearest) ? furthest : 1.0);
  if (!std::isfinite(near_m) || !std::isfinite(far_m) || near_m < 0.0 || far_m < near_m) {
    return Unexpected(RangeImageError::bad_range_scale);
  }

  image::GrayImage picture;
  picture.width = size->width;
  picture.height = size->height;
  picture.depth = options.bit_depth;
  picture.pixels.assign(std::size_t{picture.width} * picture.height, 0);
  std::vector<double> pixel_range(picture.pixels.size(), std::numeric_limits<double>::infinity());
  const double brightest = options.bit_depth == image::GrayDepth::eight ? 255.0 : 65535.0;
  for (std::size_t index = 0; index < cloud.size(); ++index) {
    if (std::isnan(ranges[index])) continue;
    PixelIndex pixel = pixel_of(cloud, index);
    if (options.last_layer_on_top) pixel.row = picture.height - 1 - pixel.row;
    const std::size_t slot = std::size_t{pixel.row} * picture.width + pixel.column;
    if (!(ranges[index] < pixel_range[slot])) continue;  // keep the nearest echo
    pixel_range[slot] = ranges[index];
    // near -> brightest, far -> 1: level 0 stays reserved for "no echo".
    const double nearness = far_m > near_m ? std::clamp((far_m - ranges[index]) / (far_m - near_m), 0.0, 1.0) : 1.0;
    picture.pixels[slot] = static_cast<std::uint16_t>(std::lround(1.0 + nearness * (brightest - 1.0)));
  }
  return picture;
}

Expected<std::string, RangeImageError> encode_range_image_png(const PointCloud& cloud,
                                                              const RangeImageOptions& options) {
  const Expected<image::GrayImage, RangeImageError> picture = make_range_image(cloud, options);
  if (!picture) return Unexpected(picture.error());
  Expected<std::string, image::PngError> png = image::encode_gray_png(*picture);
  if (!png) return Unexpected(from_png_error(png.error()));
  return std::move(*png);
}

Expected<std::size_t, RangeImageError> write_range_image_png(const std::filesystem::path& path,
                                                              const PointCloud& cloud,
                                                              const RangeImageOptions& options) {
  const Expected<std::string, RangeImageError> png = encode_range_image_png(cloud, options);
  if (!png) return Unexpected(png.error());
  const Expected<std::size_t, CloudIoError> written = write_file_bytes(path, *png);
  if (!written) {
    return Unexpected(written.error() == CloudIoError::cannot_open_file ? RangeImageError::cannot_open_file
                                                                        : RangeImageError::io_failed);
  }
  return *written;
}

}  // namespace ldoem::cloud
