#include "synthetic_scan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace ldoem::cloud::testing {
namespace {

constexpr double no_hit = std::numeric_limits<double>::infinity();

double hit_floor(const Eigen::Vector3d& direction, const SyntheticScene& scene) {
  if (direction.z() >= 0.0) return no_hit;
  return scene.floor_z_m / direction.z();
}

double hit_wall(const Eigen::Vector3d& direction, const SyntheticScene& scene) {
  if (direction.x() <= 0.0) return no_hit;
  return scene.wall_x_m / direction.x();
}

// Side of a vertical cylinder, first crossing only (the scanner is outside it).
double hit_cylinder(const Eigen::Vector3d& direction, const SyntheticScene& scene) {
  const Eigen::Vector2d d = direction.head<2>();
  const Eigen::Vector2d o = -scene.cylinder_centre_xy;
  const double a = d.squaredNorm();
  const double b = 2.0 * o.dot(d);
  const double c = o.squaredNorm() - scene.cylinder_radius_m * scene.cylinder_radius_m;
  const double discriminant = b * b - 4.0 * a * c;
  if (a <= 0.0 || discriminant < 0.0) return no_hit;
  const double t = (-b - std::sqrt(discriminant)) / (2.0 * a);
  const double z = t * direction.z();
  if (t <= 0.0 || z < scene.floor_z_m || z > scene.floor_z_m + scene.cylinder_length_m) return no_hit;
  return t;
}

double hit_box(const Eigen::Vector3d& direction, const SyntheticScene& scene) {
  double enter = 0.0;
  double leave = no_hit;
  for (int axis = 0; axis < 3; ++axis) {
    if (direction(axis) == 0.0) {
      if (0.0 < scene.box_min(axis) || 0.0 > scene.box_max(axis)) return no_hit;
      continue;
    }
    double t0 = scene.box_min(axis) / direction(axis);
    double t1 = scene.box_max(axis) / direction(axis);
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
  }
  return enter <= leave && enter > 0.0 ? enter : no_hit;
}

}  // namespace

double TestNoise::uniform() {
  state_ += 0x9E3779B97F4A7C15ULL;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return (static_cast<double>(z >> 11) + 1.0) / 9007199254740992.0;  // (0, 1]
}

double TestNoise::normal() {
  const double r1 = uniform();
  const double r2 = uniform();
  return std::sqrt(-2.0 * std::log(r1)) * std::cos(2.0 * std::numbers::pi * r2);
}

PointCloud synthetic_scan(const SyntheticScene& scene) {
  PointCloud cloud(CloudChannels{.intensity = false, .ring = true, .image_position = true});
  TestNoise noise(scene.seed);
  constexpr double degree = std::numbers::pi / 180.0;
  const auto layers = static_cast<std::uint32_t>(std::lround((scene.tilt_max_deg - scene.tilt_min_deg) / scene.tilt_step_deg)) + 1;
  const auto beams = static_cast<std::uint32_t>(std::lround((scene.head_max_deg - scene.head_min_deg) / scene.head_step_deg)) + 1;
  for (std::uint32_t layer = 0; layer < layers; ++layer) {
    const double tilt = (scene.tilt_min_deg + layer * scene.tilt_step_deg) * degree;
    for (std::uint32_t beam = 0; beam < beams; ++beam) {
      const double head = (scene.head_min_deg + beam * scene.head_step_deg) * degree;
      const Eigen::Vector3d direction(std::cos(tilt) * std::cos(head), std::cos(tilt) * std::sin(head), std::sin(tilt));
      const double range = std::min({hit_floor(direction, scene), hit_wall(direction, scene),
                                     hit_cylinder(direction, scene), hit_box(direction, scene)});
      if (!std::isfinite(range)) continue;
      const Eigen::Vector3d point = (range + scene.range_sigma_m * noise.normal()) * direction;
      PointRecord record;
      record.position = Point3f{static_cast<float>(point.x()), static_cast<float>(point.y()), static_cast<float>(point.z())};
      record.ring = static_cast<std::uint16_t>(layer);
      record.image_position = ImagePosition{layer, beam};
      cloud.push_back(record);
    }
  }
  const Eigen::Vector3d stray_min(scene.cylinder_centre_xy.x() - 0.5, scene.cylinder_centre_xy.y() - 0.5, scene.floor_z_m);
  const Eigen::Vector3d stray_size(1.0, 1.0, 1.1);
  for (std::uint32_t stray = 0; stray < scene.stray_points; ++stray) {
    const Eigen::Vector3d point = stray_min + Eigen::Vector3d(noise.uniform(), noise.uniform(), noise.uniform()).cwiseProduct(stray_size);
    PointRecord record;
    record.position = Point3f{static_cast<float>(point.x()), static_cast<float>(point.y()), static_cast<float>(point.z())};
    cloud.push_back(record);
  }
  return cloud;
}

}  // namespace ldoem::cloud::testing
