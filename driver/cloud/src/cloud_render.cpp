#include "ldoem/cloud/cloud_render.hpp"

#include "ldoem/cloud/cloud_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace ldoem::cloud {
namespace {

using base::Expected;
using base::Unexpected;

constexpr std::uint32_t kMinSide = 16;
constexpr std::uint32_t kMaxSide = 8192;
constexpr double kLowPercentile = 0.01;  // the view fits the central 98 % of the points
constexpr double kHighPercentile = 0.99;
constexpr double kViewPitch_rad = 35.0 * std::numbers::pi / 180.0;  // looking down at the scene
constexpr std::array<std::uint8_t, 3> kBackground{22, 24, 28};

struct Vec3 {
  double x, y, z;
  Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  double dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
  Vec3 cross(const Vec3& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
  Vec3 unit() const {
    const double n = std::sqrt(dot(*this));
    return {x / n, y / n, z / n};
  }
};

double percentile(std::vector<double> values, double fraction) {
  const auto index = static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index), values.end());
  return values[index];
}

// Blue (low) through cyan, green and yellow to red (high): easy to read on a dark background.
std::array<double, 3> colour_map(double t) {
  static constexpr std::array<std::array<double, 3>, 5> kStops{{
      {0.18, 0.30, 0.95}, {0.10, 0.80, 0.90}, {0.30, 0.85, 0.30}, {0.98, 0.85, 0.15}, {0.95, 0.25, 0.15}}};
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(t), kStops.size() - 2);
  const double f = t - static_cast<double>(i);
  return {kStops[i][0] + f * (kStops[i + 1][0] - kStops[i][0]), kStops[i][1] + f * (kStops[i + 1][1] - kStops[i][1]),
          kStops[i][2] + f * (kStops[i + 1][2] - kStops[i][2])};
}

}  // namespace

std::string_view to_string(RenderError error) {
  switch (error) {
    case RenderError::no_points: return "no_points";
    case RenderError::no_intensity: return "no_intensity";
    case RenderError::bad_size: return "bad_size";
    case RenderError::png_failed: return "png_failed";
    case RenderError::cannot_open_file: return "cannot_open_file";
    case RenderError::io_failed: return "io_failed";
  }
  return "unknown";
}

Expected<image::RgbImage, RenderError> render_cloud(const PointCloud& cloud, const RenderOptions& options) {
  if (options.width < kMinSide || options.width > kMaxSide || options.height < kMinSide || options.height > kMaxSide) {
    return Unexpected(RenderError::bad_size);
  }
  const bool by_intensity = options.colour == RenderColour::intensity;
  if (by_intensity && !cloud.channels().intensity) return Unexpected(RenderError::no_intensity);
  std::vector<Vec3> points;
  std::vector<double> values;  // what the colour shows, per point
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point3f& p = cloud.positions()[i];
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.z_m)) continue;
    points.push_back({p.x_m, p.y_m, p.z_m});
    values.push_back(by_intensity ? cloud.intensities()[i] : p.z_m);
  }
  if (points.empty()) return Unexpected(RenderError::no_points);

  std::vector<double> xs, ys, zs;
  for (const Vec3& p : points) {
    xs.push_back(p.x);
    ys.push_back(p.y);
    zs.push_back(p.z);
  }
  const Vec3 low{percentile(xs, kLowPercentile), percentile(ys, kLowPercentile), percentile(zs, kLowPercentile)};
  const Vec3 high{percentile(xs, kHighPercentile), percentile(ys, kHighPercentile), percentile(zs, kHighPercentile)};
  const double value_low = percentile(values, kLowPercentile);
  const double value_high = percentile(values, kHighPercentile);
  const Vec3 target = (low + high) * 0.5;
  const double radius = std::max(1.0, 0.5 * std::sqrt((high - low).dot(high - low)));

  // Look from the scanner's side towards the middle of the cloud, pitched down.
  Vec3 heading{target.x, target.y, 0.0};
  heading = heading.dot(heading) > 1e-12 ? heading.unit() : Vec3{1.0, 0.0, 0.0};
  const Vec3 forward = (heading * std::cos(kViewPitch_rad) + Vec3{0.0, 0.0, -std::sin(kViewPitch_rad)}).unit();
  const double half_fov = 0.5 * options.horizontal_fov_deg * std::numbers::pi / 180.0;
  const double aspect = static_cast<double>(options.height) / options.width;
  const double fit_angle = std::atan(std::tan(half_fov) * std::min(1.0, aspect));
  // The bounding sphere is a loose fit for the flat scenes scans are: come 25 % closer than it.
  const Vec3 eye = target - forward * (0.75 * radius / std::sin(fit_angle));
  const Vec3 right = forward.cross({0.0, 0.0, 1.0}).unit();
  const Vec3 up = right.cross(forward);
  const double focal_px = 0.5 * options.width / std::tan(half_fov);

  const std::size_t pixel_count = std::size_t{options.width} * options.height;
  const double splat_px = 0.5 * std::sqrt(0.35 * static_cast<double>(pixel_count) / static_cast<double>(points.size()));
  std::vector<float> depth(pixel_count, std::numeric_limits<float>::infinity());
  image::RgbImage picture{options.width, options.height, std::vector<std::uint8_t>(pixel_count * 3)};
  for (std::size_t i = 0; i < pixel_count; ++i) std::copy(kBackground.begin(), kBackground.end(), &picture.pixels[3 * i]);
  const double near_depth = std::max(1e-3, (eye - target).dot(forward) * -1.0 - radius);
  const double far_depth = (target - eye).dot(forward) + radius;
  for (std::size_t n = 0; n < points.size(); ++n) {
    const Vec3 d = points[n] - eye;
    const double z = d.dot(forward);
    if (!(z > 1e-3)) continue;
    const double u = 0.5 * options.width + focal_px * d.dot(right) / z;
    const double v = 0.5 * options.height - focal_px * d.dot(up) / z;
    if (!(u > -8.0 && u < options.width + 8.0 && v > -8.0 && v < options.height + 8.0)) continue;
    // Nearer points are drawn larger, as they would look, around the size at which the points
    // would tile about a third of the picture.
    const int splat = std::clamp(static_cast<int>(splat_px * (target - eye).dot(forward) / z + 0.5), 1, 5);
    const double range = value_high > value_low ? value_high - value_low : 1.0;
    auto rgb = colour_map((values[n] - value_low) / range);
    const double shade = 1.0 - 0.3 * std::clamp((z - near_depth) / std::max(1e-9, far_depth - near_depth), 0.0, 1.0);
    const std::array<std::uint8_t, 3> colour{static_cast<std::uint8_t>(255.0 * rgb[0] * shade),
                                             static_cast<std::uint8_t>(255.0 * rgb[1] * shade),
                                             static_cast<std::uint8_t>(255.0 * rgb[2] * shade)};
    const int cu = static_cast<int>(std::floor(u));
    const int cv = static_cast<int>(std::floor(v));
    for (int dv = -splat + 1; dv < splat; ++dv) {
      for (int du = -splat + 1; du < splat; ++du) {
        const int x = cu + du;
        const int y = cv + dv;
        if (x < 0 || y < 0 || x >= static_cast<int>(options.width) || y >= static_cast<int>(options.height)) continue;
        const std::size_t pixel = static_cast<std::size_t>(y) * options.width + static_cast<std::size_t>(x);
        if (static_cast<float>(z) >= depth[pixel]) continue;
        depth[pixel] = static_cast<float>(z);
        std::copy(colour.begin(), colour.end(), &picture.pixels[3 * pixel]);
      }
    }
  }
  return picture;
}

Expected<std::string, RenderError> encode_render_png(const PointCloud& cloud, const RenderOptions& options) {
  const auto picture = render_cloud(cloud, options);
  if (!picture) return Unexpected(picture.error());
  auto png = image::encode_rgb_png(*picture);
  if (!png) return Unexpected(RenderError::png_failed);
  return std::move(*png);
}

Expected<std::size_t, RenderError> write_render_png(const std::filesystem::path& path, const PointCloud& cloud,
                                                    const RenderOptions& options) {
  const auto png = encode_render_png(cloud, options);
  if (!png) return Unexpected(png.error());
  const auto written = write_file_bytes(path, *png);
  if (!written) {
    return Unexpected(written.error() == CloudIoError::cannot_open_file ? RenderError::cannot_open_file
                                                                        : RenderError::io_failed);
  }
  return *written;
}

}  // namespace ldoem::cloud
