#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>

#include <Eigen/Geometry>

#include "ldoem/cloud/fitting.hpp"
#include "synthetic_scan.hpp"

namespace ldoem::cloud {
namespace {

using testing::SyntheticScene;
using testing::TestNoise;

// The brief's scene: 195 mm diameter, 0.998 m cylinder ~2.5 m away, wall at 4.18 m, sigma 1.5 mm.
CylinderSegmentationOptions corridor_options() {
  CylinderSegmentationOptions options;
  options.plane.inlier_distance_m = 0.006;
  options.plane.iterations = 300;
  options.plane.seed = 7;
  options.max_planes = 3;
  options.min_plane_inliers = 8000;
  options.seed_region = SeedRegion{Eigen::Vector3d(2.4, 0.3, 0.0), 0.8};
  options.cylinder.inlier_distance_m = 0.005;
  options.cylinder.iterations = 400;
  options.cylinder.seed = 11;
  options.cylinder.axis_hint = AxisHint{Eigen::Vector3d::UnitZ(), 5.0 * std::numbers::pi / 180.0};
  options.cylinder.max_radius_m = 0.5;
  return options;
}

class CorridorScan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new SyntheticScene;
    points_ = new std::vector<Eigen::Vector3d>(positions_of(testing::synthetic_scan(*scene_)));
  }
  static void TearDownTestSuite() {
    delete points_;
    delete scene_;
  }
  static SyntheticScene* scene_;
  static std::vector<Eigen::Vector3d>* points_;
};

SyntheticScene* CorridorScan::scene_ = nullptr;
std::vector<Eigen::Vector3d>* CorridorScan::points_ = nullptr;

const PlaneFit* plane_facing(const std::vector<PlaneFit>& planes, const Eigen::Vector3d& normal) {
  for (const PlaneFit& plane : planes) {
    if (std::abs(plane.normal.dot(normal)) > 0.999) return &plane;
  }
  return nullptr;
}

TEST_F(CorridorScan, SegmentedVerticalCylinder_MatchesDiameterLengthAndAxis) {
  const auto result = segment_cylinder(*points_, corridor_options());
  ASSERT_TRUE(result) << to_string(result.error());
  const CylinderFit& cylinder = result->cylinder;
  EXPECT_NEAR(2.0 * cylinder.radius_m, 0.195, 0.003);
  EXPECT_NEAR(cylinder.length_m, 0.998, 0.02);
  EXPECT_NEAR(cylinder.axis_point.x(), 2.5, 0.003);
  EXPECT_NEAR(cylinder.axis_point.y(), 0.3, 0.003);
  EXPECT_GT(cylinder.axis_direction.z(), std::cos(1.0 * std::numbers::pi / 180.0));
  EXPECT_LT(cylinder.rms_m, 0.0025);
  EXPECT_GT(cylinder.inlier_count, 2000U);
  std::cout << "[ measured ] diameter " << 2000.0 * cylinder.radius_m << " mm, length " << cylinder.length_m
            << " m, axis (" << cylinder.axis_point.x() << ", " << cylinder.axis_point.y() << "), inliers "
            << cylinder.inlier_count << " of " << result->candidate_count << ", rms " << 1000.0 * cylinder.rms_m
            << " mm\n";
}

TEST_F(CorridorScan, SegmentedPlanes_WallAtItsDistanceAndFloorBelow) {
  const auto result = segment_cylinder(*points_, corridor_options());
  ASSERT_TRUE(result);
  const PlaneFit* wall = plane_facing(result->planes, Eigen::Vector3d::UnitX());
  const PlaneFit* floor = plane_facing(result->planes, Eigen::Vector3d::UnitZ());
  ASSERT_NE(wall, nullptr);
  ASSERT_NE(floor, nullptr);
  EXPECT_NEAR(wall->offset_m, 4.18, 0.005);
  EXPECT_NEAR(floor->offset_m, 0.5, 0.005);
  EXPECT_LT(wall->rms_m, 0.003);
  std::cout << "[ measured ] wall " << wall->offset_m << " m (rms " << 1000.0 * wall->rms_m << " mm), floor "
            << floor->offset_m << " m\n";
}

TEST_F(CorridorScan, FreeAxisCylinder_FindsVerticalAxisAndDiameter) {
  CylinderSegmentationOptions options = corridor_options();
  options.cylinder.axis_hint.reset();
  options.cylinder.iterations = 600;
  const auto result = segment_cylinder(*points_, options);
  ASSERT_TRUE(result) << to_string(result.error());
  EXPECT_NEAR(2.0 * result->cylinder.radius_m, 0.195, 0.003);
  EXPECT_NEAR(result->cylinder.length_m, 0.998, 0.02);
  EXPECT_GT(std::abs(result->cylinder.axis_direction.z()), std::cos(1.0 * std::numbers::pi / 180.0));
}

TEST_F(CorridorScan, SameSeed_GivesIdenticalResults) {
  const auto first = segment_cylinder(*points_, corridor_options());
  const auto second = segment_cylinder(*points_, corridor_options());
  ASSERT_TRUE(first);
  ASSERT_TRUE(second);
  EXPECT_EQ(first->cylinder.radius_m, second->cylinder.radius_m);
  EXPECT_EQ(first->cylinder.inliers, second->cylinder.inliers);
  ASSERT_EQ(first->planes.size(), second->planes.size());
  EXPECT_EQ(first->planes[0].offset_m, second->planes[0].offset_m);
}

TEST(PlaneFit, NoisyTiltedPlaneWithOutliers_RecoversNormalAndOffset) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const double offset_m = 1.25;
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d v = normal.cross(u);
  TestNoise noise(3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 2000; ++i) {
    const double a = 4.0 * noise.uniform() - 2.0;
    const double b = 4.0 * noise.uniform() - 2.0;
    points.push_back(offset_m * normal + a * u + b * v + 0.0015 * noise.normal() * normal);
  }
  for (int i = 0; i < 500; ++i) points.emplace_back(noise.uniform() * 3, noise.uniform() * 3, noise.uniform() * 3);
  const auto fit = fit_plane_ransac(points, PlaneRansacOptions{0.005, 200, 5});
  ASSERT_TRUE(fit);
  EXPECT_GT(fit->normal.dot(normal), std::cos(0.2 * std::numbers::pi / 180.0));
  EXPECT_NEAR(fit->offset_m, offset_m, 0.001);
  EXPECT_NEAR(fit->rms_m, 0.0015, 0.0003);
  EXPECT_GE(fit->inlier_count, 1950U);
  EXPECT_EQ(fit->inliers.size(), fit->inlier_count);
}

TEST(PlaneFit, TwoPoints_IsTooFew) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}};
  const auto fit = fit_plane_ransac(points);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::too_few_points);
}

TEST(PlaneFit, CollinearPoints_IsDegenerate) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 50; ++i) points.emplace_back(0.1 * i, 0.2 * i, -0.05 * i);
  const auto fit = fit_plane_ransac(points);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::degenerate_points);
}

TEST(PlaneFit, NanPoint_IsNonFinite) {
  std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {std::nan(""), 0, 0}};
  const auto fit = fit_plane_ransac(points);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::non_finite_point);
}

TEST(PlaneFit, ZeroThreshold_IsBadOptions) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const auto fit = fit_plane_ransac(points, PlaneRansacOptions{0.0, 10, 1});
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::bad_options);
}

TEST(CylinderFit, FourPoints_IsTooFew) {
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const auto fit = fit_cylinder_ransac(points);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::too_few_points);
}

TEST(CylinderFit, CollinearPoints_IsDegenerate) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 50; ++i) points.emplace_back(1.0, 2.0, 0.02 * i);
  for (const bool hinted : {false, true}) {
    CylinderRansacOptions options;
    if (hinted) options.axis_hint = AxisHint{};
    const auto fit = fit_cylinder_ransac(points, options);
    ASSERT_FALSE(fit);
    EXPECT_EQ(fit.error(), FitError::degenerate_points);
  }
}

TEST(CylinderFit, InfinitePoint_IsNonFinite) {
  std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1},
                                      {std::numeric_limits<double>::infinity(), 0, 0}};
  const auto fit = fit_cylinder_ransac(points);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::non_finite_point);
}

TEST(CylinderFit, PlanarPointsOnly_FindsNoCylinderInRadiusRange) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) points.emplace_back(2.0, 0.01 * i, 0.01 * j);
  }
  CylinderRansacOptions options;
  options.axis_hint = AxisHint{};
  options.max_radius_m = 0.2;
  const auto fit = fit_cylinder_ransac(points, options);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error(), FitError::no_model_found);
}

std::vector<Eigen::Vector3d> leaning_cylinder(double lean_deg) {
  const double lean = lean_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d axis(std::sin(lean), 0.0, std::cos(lean));
  const Eigen::Vector3d u = axis.unitOrthogonal();
  const Eigen::Vector3d v = axis.cross(u);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 36; ++j) {
      const double angle = j * 2.0 * std::numbers::pi / 36.0;
      points.push_back(0.02 * i * axis + 0.1 * (std::cos(angle) * u + std::sin(angle) * v));
    }
  }
  return points;
}

TEST(CylinderFit, RefinedAxisLeavingHintCone_IsRejected) {
  // Leans 8 deg; the vertical hint finds it (slices fit a vertical circle), refinement tilts
  // the axis to 8 deg, outside the 3 deg cone.
  CylinderRansacOptions options;
  options.axis_hint = AxisHint{Eigen::Vector3d::UnitZ(), 3.0 * std::numbers::pi / 180.0};
  const auto hinted = fit_cylinder_ransac(leaning_cylinder(8.0), options);
  ASSERT_FALSE(hinted);
  EXPECT_EQ(hinted.error(), FitError::axis_outside_tolerance);
  options.axis_hint->max_angle_rad = 10.0 * std::numbers::pi / 180.0;
  const auto wider = fit_cylinder_ransac(leaning_cylinder(8.0), options);
  ASSERT_TRUE(wider) << to_string(wider.error());
  EXPECT_NEAR(wider->radius_m, 0.1, 1e-6);
}

TEST(CylinderFit, ExactLeaningCylinderFreeAxis_RecoversAxisRadiusLength) {
  const double lean = 20.0 * std::numbers::pi / 180.0;
  const Eigen::Vector3d axis(std::sin(lean), 0.0, std::cos(lean));
  const auto fit = fit_cylinder_ransac(leaning_cylinder(20.0), CylinderRansacOptions{});
  ASSERT_TRUE(fit) << to_string(fit.error());
  EXPECT_NEAR(fit->radius_m, 0.1, 1e-6);
  EXPECT_NEAR(fit->length_m, 0.78, 1e-6);
  EXPECT_GT(fit->axis_direction.dot(axis), 1.0 - 1e-9);
  EXPECT_NEAR((fit->axis_point - 0.39 * axis).norm(), 0.0, 1e-6);
  EXPECT_LT(fit->rms_m, 1e-6);
}

TEST(Segmentation, NanPoint_IsNonFinite) {
  std::vector<Eigen::Vector3d> points(10, Eigen::Vector3d::Zero());
  points[3].y() = std::nan("");
  const auto result = segment_cylinder(points, CylinderSegmentationOptions{});
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error(), FitError::non_finite_point);
}

TEST(Positions, FinitePositions_DropsNanPoints) {
  PointCloud cloud;
  PointRecord record;
  cloud.push_back(record);
  record.position.x_m = std::nanf("");
  cloud.push_back(record);
  EXPECT_EQ(positions_of(cloud).size(), 2U);
  EXPECT_EQ(finite_positions(cloud).size(), 1U);
}

}  // namespace
}  // namespace ldoem::cloud
