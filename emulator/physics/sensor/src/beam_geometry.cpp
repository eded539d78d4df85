#include <ldoem/sensor/beam_geometry.hpp>

#include <cmath>

namespace ldoem::sensor {

Eigen::Isometry3d world_from_optical(const scene::Pose& pivot, const Eigen::Vector3d& optical_offset_m,
                                     double tilt_rad) {
  Eigen::Isometry3d world_from_pivot = Eigen::Isometry3d::Identity();
  world_from_pivot.translate(pivot.position_m);
  world_from_pivot.rotate(pivot.orientation.normalized());
  const Eigen::AngleAxisd tilt(-tilt_rad, Eigen::Vector3d::UnitY());  // D5: R_y(-phi)
  return world_from_pivot * tilt * Eigen::Translation3d(optical_offset_m);
}

Eigen::Isometry3d world_from_optical(const scene::ScannerConfig& scanner, double tilt_rad) {
  return world_from_optical(scanner.pivot_pose, scanner.optical_offset_m, tilt_rad);
}

Eigen::Vector3d beam_direction_optical(double head_angle_rad) {
  return {std::cos(head_angle_rad), std::sin(head_angle_rad), 0.0};
}

raycast::Ray beam_ray(const scene::ScannerConfig& scanner, double head_angle_rad, double tilt_rad,
                      double max_range_m) {
  return beam_ray(world_from_optical(scanner, tilt_rad), head_angle_rad, max_range_m);
}

raycast::Ray beam_ray(const Eigen::Isometry3d& world_from_opt, double head_angle_rad, double max_range_m) {
  return raycast::Ray{
      .origin_m = world_from_opt.translation(),
      .direction = (world_from_opt.linear() * beam_direction_optical(head_angle_rad)).normalized(),
      .max_range_m = max_range_m,
  };
}

Eigen::Vector3d beam_point_world(const scene::ScannerConfig& scanner, double head_angle_rad, double tilt_rad,
                                 double range_m) {
  return world_from_optical(scanner, tilt_rad) * (range_m * beam_direction_optical(head_angle_rad));
}

}  // namespace ldoem::sensor
