#include "ldoem/cloud/cloud_render.hpp"

#include "ldoem/cloud/cloud_file.hpp"

#include "bitmap_font.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <optional>
#include <string>
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


using detail::Rgb;

constexpr Rgb kText{225, 228, 232};
constexpr Rgb kDim{150, 155, 165};
constexpr Rgb kSaturated{245, 110, 245};  // ECHO 65535: the model's ceiling, not a value
constexpr double kEchoCeiling = 65535.0;
constexpr int kScale = 2;                  // font scale: 10 x 14 pixel characters
constexpr int kTitleBand = 34;
constexpr int kLegendBand = 190;
constexpr std::uint32_t kMinAnnotatedWidth = 480;
constexpr std::uint32_t kMinAnnotatedHeight = 300;

Rgb to_rgb(const std::array<double, 3>& colour, double shade = 1.0) {
  return {static_cast<std::uint8_t>(255.0 * colour[0] * shade), static_cast<std::uint8_t>(255.0 * colour[1] * shade),
          static_cast<std::uint8_t>(255.0 * colour[2] * shade)};
}

// Shortest text of value with at most `decimals` decimals ("2", "2.5", "-0.25").
std::string number_text(double value, int decimals) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  std::string text(buffer, result.ptr);
  if (text.find('.') != std::string::npos) {
    while (text.back() == '0') text.pop_back();
    if (text.back() == '.') text.pop_back();
  }
  return text == "-0" ? "0" : text;
}

// What the colours show: the value per point on the scale the legend explains.
struct ColourScale {
  bool logarithmic = false;  // intensity: log10(ECHO)
  double low = 0.0;          // scale values at the ends of the colour bar
  double high = 1.0;
  std::string title;         // the legend's heading with the unit
  std::size_t saturated = 0; // points at the ECHO ceiling, drawn in kSaturated
  std::size_t points = 0;
  double fraction(double value) const { return high > low ? (value - low) / (high - low) : 0.5; }
  std::string label(double scale_value) const {
    return logarithmic ? number_text(std::round(std::pow(10.0, scale_value)), 0) : number_text(scale_value, 2);
  }
};

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

namespace {

struct Camera {
  Vec3 eye, forward, right, up;
  double focal_px = 1.0, centre_u = 0.0, centre_v = 0.0;
  struct Pixel {
    double u, v, depth;
  };
  std::optional<Pixel> project(const Vec3& point) const {
    const Vec3 d = point - eye;
    const double z = d.dot(forward);
    if (!(z > 1e-3)) return std::nullopt;
    return Pixel{centre_u + focal_px * d.dot(right) / z, centre_v - focal_px * d.dot(up) / z, z};
  }
};

ColourScale make_scale(bool by_intensity, std::vector<double>& values) {
  ColourScale scale;
  scale.points = values.size();
  if (!by_intensity) {
    scale.title = "height z (m)";
    scale.low = percentile(values, kLowPercentile);
    scale.high = percentile(values, kHighPercentile);
    return scale;
  }
  // ECHO spans decades (D6: 1000 at the threshold, ~1/l^2), so the colours follow log10(ECHO),
  // stretched over the central 98 % of the echoes below the ceiling; echoes at the ceiling say
  // only "at least 65535" and get a colour of their own.
  scale.logarithmic = true;
  scale.title = "ECHO (log scale)";
  std::vector<double> below;
  for (double& value : values) {
    if (value >= kEchoCeiling) {
      ++scale.saturated;
      value = std::numeric_limits<double>::infinity();
      continue;
    }
    value = std::log10(std::max(1.0, value));
    below.push_back(value);
  }
  if (below.empty()) {
    scale.low = 3.0;
    scale.high = std::log10(kEchoCeiling);
  } else {
    scale.low = percentile(below, kLowPercentile);
    scale.high = percentile(below, kHighPercentile);
  }
  return scale;
}

// Metre or half-metre ticks, whichever gives a handful over the extent.
double tick_step(double extent) { return extent < 2.0 ? 0.5 : (extent < 6.0 ? 1.0 : (extent < 15.0 ? 2.0 : 5.0)); }

void draw_axes(image::RgbImage& picture, const Camera& camera, const Vec3& low, const Vec3& high) {
  // Three edges of the cloud's box (its central 98 %) meeting at its far left floor corner, as
  // in a 3D plot: x along the floor's left (+y) edge, y across the floor at the far end, z up
  // the far left corner; each ticked and labelled in metres of the scanner frame. The far end
  // is in view and beside the data; the near end of the box, under and behind the camera's
  // look, mostly is not.
  struct Axis {
    Vec3 start;
    Vec3 direction;
    double from, to;
    const char* name;
    Rgb colour;
  };
  const std::array<Axis, 3> axes{{
      {{0, high.y, low.z}, {1, 0, 0}, low.x, high.x, "x", {235, 95, 85}},
      {{high.x, 0, low.z}, {0, 1, 0}, low.y, high.y, "y", {110, 215, 110}},
      {{high.x, high.y, 0}, {0, 0, 1}, low.z, high.z, "z", {110, 160, 250}},
  }};
  const auto in_view = [&picture](const auto& point) {
    return point && point->u >= 0 && point->v >= 0 && point->u < picture.width && point->v < picture.height;
  };
  for (const Axis& axis : axes) {
    const auto a = camera.project(axis.start + axis.direction * axis.from);
    const auto b = camera.project(axis.start + axis.direction * axis.to);
    if (!a || !b) continue;
    detail::draw_line(picture, a->u, a->v, b->u, b->v, axis.colour);
    const double step = tick_step(axis.to - axis.from);
    std::optional<std::pair<int, int>> last_tick;  // the last one in view: x's name goes there
    for (double value = std::ceil(axis.from / step) * step; value <= axis.to + 1e-9; value += step) {
      const auto tick = camera.project(axis.start + axis.direction * value);
      if (!in_view(tick)) continue;
      const int u = static_cast<int>(tick->u);
      const int v = static_cast<int>(tick->v);
      if (!last_tick) last_tick = std::pair{u, v};
      detail::fill_rect(picture, u - 2, v - 2, u + 3, v + 3, axis.colour);
      const std::string label = number_text(value, 1);
      // z and x labels to the left of their tick (outside the box), y labels below it.
      if (axis.name[0] == 'y') {
        detail::draw_text(picture, u - detail::text_width(label, kScale) / 2, v + 8, label, axis.colour, kScale);
      } else {
        detail::draw_text(picture, u - 16 - detail::text_width(label, kScale), v - 7, label, axis.colour, kScale);
      }
    }
    const std::string name = std::string(axis.name) + " (m)";
    if (axis.name[0] == 'x') {
      // Its far end is where y and z begin: the name goes at the nearest tick in view instead.
      if (last_tick) {
        detail::draw_text(picture, last_tick->first - 8 - detail::text_width(name, kScale), last_tick->second - 30, name,
                          axis.colour, kScale);
      }
    } else if (axis.name[0] == 'z') {
      // Left of its top end: the wall's top edge is right of it.
      detail::draw_text(picture, static_cast<int>(b->u) - 16 - detail::text_width(name, kScale), static_cast<int>(b->v) - 7,
                        name, axis.colour, kScale);
    } else {
      detail::draw_text(picture, static_cast<int>(b->u) + 10, static_cast<int>(b->v) - 20, name, axis.colour, kScale);
    }
  }
}

void draw_scale_bar(image::RgbImage& picture, const Camera& camera, double target_depth, int plot_bottom) {
  // A perspective picture has no single scale: the bar holds at the depth of the cloud's middle.
  const double pixels_per_metre = camera.focal_px / target_depth;
  double metres = 0.1;
  for (double candidate : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0}) {
    if (candidate * pixels_per_metre <= 220.0) metres = candidate;
  }
  const int length = static_cast<int>(std::lround(metres * pixels_per_metre));
  const int x = 20;
  const int y = plot_bottom - 30;
  detail::fill_rect(picture, x, y, x + length, y + 4, kText);
  detail::fill_rect(picture, x, y - 6, x + 2, y + 10, kText);
  detail::fill_rect(picture, x + length - 2, y - 6, x + length, y + 10, kText);
  detail::draw_text(picture, x, y - 24, number_text(metres, 1) + " m at the depth of the cloud centre", kText, kScale);
}

void draw_legend(image::RgbImage& picture, const ColourScale& scale) {
  const int x = static_cast<int>(picture.width) - kLegendBand + 16;
  const int top = kTitleBand + 40;
  const int bottom = static_cast<int>(picture.height) - (scale.logarithmic ? 110 : 60);
  detail::fill_rect(picture, static_cast<int>(picture.width) - kLegendBand, kTitleBand,
                    static_cast<int>(picture.width), static_cast<int>(picture.height), {30, 33, 38});
  detail::draw_text(picture, x - 8, kTitleBand + 12, scale.title, kText, scale.title.size() > 14 ? 1 : kScale);
  for (int y = top; y <= bottom; ++y) {
    const double t = 1.0 - static_cast<double>(y - top) / std::max(1, bottom - top);
    detail::fill_rect(picture, x, y, x + 26, y + 1, to_rgb(colour_map(t)));
  }
  constexpr int kTicks = 5;
  for (int i = 0; i < kTicks; ++i) {
    const double t = static_cast<double>(i) / (kTicks - 1);
    const int y = bottom - static_cast<int>(std::lround(t * (bottom - top)));
    detail::fill_rect(picture, x + 26, y, x + 34, y + 1, kText);
    detail::draw_text(picture, x + 40, y - 7, scale.label(scale.low + t * (scale.high - scale.low)), kText, kScale);
  }
  if (scale.logarithmic) {
    const int y = bottom + 30;
    detail::fill_rect(picture, x, y, x + 26, y + 16, kSaturated);
    detail::draw_text(picture, x + 40, y + 1, "65535", kText, kScale);
    const double percent = scale.points ? 100.0 * static_cast<double>(scale.saturated) / scale.points : 0.0;
    detail::draw_text(picture, x - 8, y + 26, "ceiling: " + number_text(percent, 0) + "% of points", kDim, 1);
  }
}

}  // namespace

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
  const ColourScale scale = make_scale(by_intensity, values);
  const Vec3 target = (low + high) * 0.5;
  const double radius = std::max(1.0, 0.5 * std::sqrt((high - low).dot(high - low)));

  // Small pictures (thumbnails, tests of the projection) get no labels: they would cover them.
  const bool annotate = options.annotate && options.width >= kMinAnnotatedWidth && options.height >= kMinAnnotatedHeight;
  const int plot_left = 0;
  const int plot_right = static_cast<int>(options.width) - (annotate ? kLegendBand : 0);
  const int plot_top = annotate ? kTitleBand : 0;
  const int plot_bottom = static_cast<int>(options.height);
  const double plot_width = plot_right - plot_left;
  const double plot_height = plot_bottom - plot_top;

  // Look from the scanner's side towards the middle of the cloud, pitched down.
  Camera camera;
  Vec3 heading{target.x, target.y, 0.0};
  heading = heading.dot(heading) > 1e-12 ? heading.unit() : Vec3{1.0, 0.0, 0.0};
  camera.forward = (heading * std::cos(kViewPitch_rad) + Vec3{0.0, 0.0, -std::sin(kViewPitch_rad)}).unit();
  const double half_fov = 0.5 * options.horizontal_fov_deg * std::numbers::pi / 180.0;
  const double aspect = plot_height / plot_width;
  const double fit_angle = std::atan(std::tan(half_fov) * std::min(1.0, aspect));
  // The bounding sphere is a loose fit for the flat scenes scans are: come 25 % closer than it.
  camera.eye = target - camera.forward * (0.75 * radius / std::sin(fit_angle));
  camera.right = camera.forward.cross({0.0, 0.0, 1.0}).unit();
  camera.up = camera.right.cross(camera.forward);
  camera.focal_px = 0.5 * plot_width / std::tan(half_fov);
  camera.centre_u = plot_left + 0.5 * plot_width;
  camera.centre_v = plot_top + 0.5 * plot_height;
  const double target_depth = (target - camera.eye).dot(camera.forward);

  const std::size_t pixel_count = std::size_t{options.width} * options.height;
  const double splat_px = 0.5 * std::sqrt(0.35 * plot_width * plot_height / static_cast<double>(points.size()));
  std::vector<float> depth(pixel_count, std::numeric_limits<float>::infinity());
  image::RgbImage picture{options.width, options.height, std::vector<std::uint8_t>(pixel_count * 3)};
  for (std::size_t i = 0; i < pixel_count; ++i) std::copy(kBackground.begin(), kBackground.end(), &picture.pixels[3 * i]);
  if (annotate) draw_axes(picture, camera, low, high);
  const double near_depth = std::max(1e-3, target_depth - radius);
  const double far_depth = target_depth + radius;
  for (std::size_t n = 0; n < points.size(); ++n) {
    const auto at = camera.project(points[n]);
    if (!at) continue;
    const double u = at->u;
    const double v = at->v;
    const double z = at->depth;
    if (!(u > plot_left - 8.0 && u < plot_right + 8.0 && v > plot_top - 8.0 && v < plot_bottom + 8.0)) continue;
    // Nearer points are drawn larger, as they would look, around the size at which the points
    // would tile about a third of the picture.
    const int splat = std::clamp(static_cast<int>(splat_px * target_depth / z + 0.5), 1, 5);
    const double shade = 1.0 - 0.3 * std::clamp((z - near_depth) / std::max(1e-9, far_depth - near_depth), 0.0, 1.0);
    const Rgb colour = std::isinf(values[n]) ? to_rgb({kSaturated[0] / 255.0, kSaturated[1] / 255.0, kSaturated[2] / 255.0}, shade)
                                             : to_rgb(colour_map(scale.fraction(values[n])), shade);
    const int cu = static_cast<int>(std::floor(u));
    const int cv = static_cast<int>(std::floor(v));
    for (int dv = -splat + 1; dv < splat; ++dv) {
      for (int du = -splat + 1; du < splat; ++du) {
        const int x = cu + du;
        const int y = cv + dv;
        if (x < plot_left || y < plot_top || x >= plot_right || y >= plot_bottom) continue;
        const std::size_t pixel = static_cast<std::size_t>(y) * options.width + static_cast<std::size_t>(x);
        if (static_cast<float>(z) >= depth[pixel]) continue;
        depth[pixel] = static_cast<float>(z);
        std::copy(colour.begin(), colour.end(), &picture.pixels[3 * pixel]);
      }
    }
  }
  if (annotate) {
    draw_scale_bar(picture, camera, target_depth, plot_bottom);
    draw_legend(picture, scale);
    detail::fill_rect(picture, 0, 0, static_cast<int>(options.width), kTitleBand, {12, 13, 16});
    const std::string title = options.title.empty() ? std::string("ldoem point cloud") : options.title;
    detail::draw_text(picture, 12, 10, title + "  |  " + std::to_string(points.size()) + " points", kText, kScale);
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
