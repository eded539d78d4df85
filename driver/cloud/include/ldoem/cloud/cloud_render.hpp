// A picture of a point cloud a person can read: a perspective view, points coloured by height
// (z, metres) or by intensity (ECHO on a log scale stretched over the central 98 % of the
// echoes; echoes at the 65535 ceiling in a colour of their own), nearer points drawn over
// farther ones, on a dark background, with a title, the axes in metres, a scale bar and a
// legend. The default
// viewpoint stands behind and above the scanner's origin, looking at the middle of the cloud, far
// enough back that the central 98 % of the points fit. Deterministic: the same cloud gives the
// same pixels.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/image/png.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::cloud {

enum class RenderColour : std::uint8_t { height, intensity };

enum class RenderError : std::uint8_t {
  no_points,          // no finite point to draw
  no_intensity,       // coloured by intensity, but the cloud has no intensity channel
  bad_size,           // width or height outside [16, 8192]
  png_failed,
  cannot_open_file,
  io_failed,
};

[[nodiscard]] std::string_view to_string(RenderError error);

struct RenderOptions {
  std::uint32_t width = 1600;
  std::uint32_t height = 1000;
  RenderColour colour = RenderColour::height;
  double horizontal_fov_deg = 70.0;
  // The line across the top (scene, scanner, settings); one line, drawn with the render's own
  // 5x7 font (ASCII; other characters show as '?').
  std::string title;
  // Title, the scanner frame's axes ticked in metres, a scale bar, the colour legend with its
  // unit. Pictures under 480 x 300 get none of them whatever this says.
  bool annotate = true;
};

[[nodiscard]] base::Expected<image::RgbImage, RenderError> render_cloud(const PointCloud& cloud,
                                                                           const RenderOptions& options = {});

// render_cloud + image::encode_rgb_png: the PNG file's bytes.
[[nodiscard]] base::Expected<std::string, RenderError> encode_render_png(const PointCloud& cloud,
                                                                         const RenderOptions& options = {});

// encode_render_png + write; returns the number of bytes written.
[[nodiscard]] base::Expected<std::size_t, RenderError> write_render_png(const std::filesystem::path& path,
                                                                           const PointCloud& cloud,
                                                                           const RenderOptions& options = {});

}  // namespace ldoem::cloud
