// D5 beam geometry: where a beam starts and where it points, for a head angle theta and a tilt
// phi. Pure functions of the scanner configuration; no state, no casting.
#pragma once

#include <ldoem/raycast/ray_caster.hpp>
#include <ldoem/scene/scene.hpp>

#include <Eigen/Geometry>

namespace ldoem::sensor {

// T_world_pivot * R_y(-phi) * Translation(offset): maps the optical frame (origin at the optical
// centre, axes of the scanner frame: x forward, y left, z up) into the world. R_y(-phi) because a
// positive tilt raises the beam plane (D5), i.e. turns +x towards +z.
[[nodiscard]] Eigen::Isometry3d world_from_optical(const scene::ScannerConfig& scanner, double tilt_rad);
// The same with the pivot somewhere else (D12 pivot_motion: the pivot's pose at the beam's time).
[[nodiscard]] Eigen::Isometry3d world_from_optical(const scene::Pose& pivot, const Eigen::Vector3d& optical_offset_m,
                                                   double tilt_rad);

// Unit direction of the beam at head angle theta (0 = +x, counter-clockwise seen from above) in
// the optical frame: (cos theta, sin theta, 0).
[[nodiscard]] Eigen::Vector3d beam_direction_optical(double head_angle_rad);

// The world ray of one beam: origin at the optical centre, unit direction, max_range_m as given.
[[nodiscard]] raycast::Ray beam_ray(const scene::ScannerConfig& scanner, double head_angle_rad,
                                    double tilt_rad, double max_range_m);
[[nodiscard]] raycast::Ray beam_ray(const Eigen::Isometry3d& world_from_optical, double head_angle_rad,
                                    double max_range_m);

// D5 point of a return at range l: T_world_pivot * R_y(-phi) * (offset + l (cos theta, sin theta, 0)).
[[nodiscard]] Eigen::Vector3d beam_point_world(const scene::ScannerConfig& scanner, double head_angle_rad,
                                               double tilt_rad, double range_m);

}  // namespace ldoem::sensor
