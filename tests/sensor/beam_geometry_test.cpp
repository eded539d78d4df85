#include <ldoem/sensor/beam_geometry.hpp>

#include <gtest/gtest.h>

#include <numbers>

#include "degrees.hpp"

namespace ldoem::sensor {
namespace {

using testing::kDeg;
constexpr double kTolerance = 1e-12;

void expect_near(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected) {
  EXPECT_TRUE(actual.isApprox(expected, 1e-12) || (actual - expected).norm() < kTolerance)
      << "actual " << actual.transpose() << " expected " << expected.transpose();
}

struct GoldenBeam {
  double head_deg;
  double tilt_deg;
  Eigen::Vector3d direction;
};

TEST(BeamGeometry, GoldenAnglesAtLevelPivot_PointWhereD5Says) {
  const scene::ScannerConfig scanner;  // pivot at the origin, no offset
  const double half = std::sqrt(0.5);
  const GoldenBeam golden[] = {
      {0, 0, {1, 0, 0}},        {90, 0, {0, 1, 0}},          {180, 0, {-1, 0, 0}},
      {270, 0, {0, -1, 0}},     {45, 0, {half, half, 0}},    {0, 30, {std::cos(30 * kDeg), 0, std::sin(30 * kDeg)}},
      {0, -30, {std::cos(30 * kDeg), 0, -std::sin(30 * kDeg)}},  {90, 30, {0, 1, 0}},
      {180, 30, {-std::cos(30 * kDeg), 0, -std::sin(30 * kDeg)}},  // behind: a raised plane dips
      {0, 90, {0, 0, 1}},
  };
  for (const GoldenBeam& beam : golden) {
    SCOPED_TRACE(::testing::Message() << "theta " << beam.head_deg << " phi " << beam.tilt_deg);
    const raycast::Ray ray = beam_ray(scanner, beam.head_deg * kDeg, beam.tilt_deg * kDeg, 30.0);
    expect_near(ray.direction, beam.direction);
    expect_near(ray.origin_m, Eigen::Vector3d::Zero());
    EXPECT_EQ(ray.max_range_m, 30.0);
  }
}

TEST(BeamGeometry, OpticalOffsetTiltsWithThePlate) {
  scene::ScannerConfig scanner;
  scanner.optical_offset_m = {0.1, 0.0, 0.2};
  // R_y(-90 deg) maps (x, y, z) to (-z, y, x).
  const raycast::Ray ray = beam_ray(scanner, 0.0, 90 * kDeg, 30.0);
  expect_near(ray.origin_m, {-0.2, 0.0, 0.1});
  expect_near(ray.direction, {0, 0, 1});
}

TEST(BeamGeometry, PivotPoseMovesAndTurnsTheBeam) {
  scene::ScannerConfig scanner;
  scanner.pivot_pose.position_m = {1, 2, 3};
  scanner.pivot_pose.orientation = Eigen::AngleAxisd(90 * kDeg, Eigen::Vector3d::UnitZ());
  scanner.optical_offset_m = {0.5, 0, 0};
  const raycast::Ray ray = beam_ray(scanner, 0.0, 0.0, 30.0);
  expect_near(ray.origin_m, {1, 2.5, 3});
  expect_near(ray.direction, {0, 1, 0});
}

TEST(BeamGeometry, PointIsOriginPlusRangeAlongDirection) {
  scene::ScannerConfig scanner;
  scanner.pivot_pose.position_m = {0.3, -0.2, 1.0};
  scanner.pivot_pose.orientation = Eigen::AngleAxisd(20 * kDeg, Eigen::Vector3d(1, 2, 3).normalized());
  scanner.optical_offset_m = {0.05, 0.01, 0.12};
  const double theta = 123 * kDeg;
  const double phi = -17 * kDeg;
  const raycast::Ray ray = beam_ray(scanner, theta, phi, 30.0);
  expect_near(beam_point_world(scanner, theta, phi, 7.5), ray.origin_m + 7.5 * ray.direction);
  // D5 formula written out literally.
  const Eigen::Vector3d literal =
      scanner.pivot_pose.position_m +
      scanner.pivot_pose.orientation *
          (Eigen::AngleAxisd(-phi, Eigen::Vector3d::UnitY()) *
           (scanner.optical_offset_m + 7.5 * Eigen::Vector3d(std::cos(theta), std::sin(theta), 0)));
  expect_near(beam_point_world(scanner, theta, phi, 7.5), literal);
  EXPECT_NEAR(ray.direction.norm(), 1.0, 1e-15);
}

}  // namespace
}  // namespace ldoem::sensor
