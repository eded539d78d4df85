// A scan of a known scene, made in the test (no emulator code, design.md): a scanner at the
// origin sweeping its beam plane in tilt, rays cast against a floor, a wall 4.18 m ahead, a
// standing cylinder ~2.5 m ahead and a box; range noise along the ray, plus stray points.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::cloud::testing {

struct SyntheticScene {
  double floor_z_m = -0.5;
  double wall_x_m = 4.18;
  Eigen::Vector2d cylinder_centre_xy{2.5, 0.3};
  double cylinder_radius_m = 0.195 / 2.0;
  double cylinder_length_m = 0.998;  // standing on the floor
  Eigen::Vector3d box_min{3.0, -0.9, -0.5};
  Eigen::Vector3d box_max{3.3, -0.6, -0.2};
  double range_sigma_m = 0.0015;
  std::uint32_t stray_points = 300;  // uniform in a box around the cylinder (mixed-pixel-like)
  std::uint64_t seed = 42;
  double head_min_deg = -30.0;
  double head_max_deg = 30.0;
  double head_step_deg = 0.25;
  double tilt_min_deg = -20.0;
  double tilt_max_deg = 15.0;
  double tilt_step_deg = 0.1;
};

// Rows are tilt layers, columns head beams; no-echo rays are left out (unorganised cloud with
// ring and image positions). Stray points come last.
PointCloud synthetic_scan(const SyntheticScene& scene);

// Deterministic standard normal draws (SplitMix64 + Box-Muller), for test data only.
class TestNoise {
 public:
  explicit TestNoise(std::uint64_t seed) : state_(seed) {}
  double uniform();  // (0, 1]
  double normal();

 private:
  std::uint64_t state_;
};

}  // namespace ldoem::cloud::testing
