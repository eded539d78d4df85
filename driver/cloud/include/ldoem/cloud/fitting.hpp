// Geometric fits on point positions, for checking scans against known scenes: RANSAC plane and
// cylinder, each refined by least squares on its inliers. Deterministic for a given seed (the
// generator is specified here, not taken from <random>'s implementation-defined distributions).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::cloud {

using base::Expected;
using base::Unexpected;

enum class FitError : std::uint8_t {
  too_few_points,          // fewer points than the model needs (plane 3, cylinder 5)
  non_finite_point,        // a NaN or infinite coordinate (filter with finite_positions first)
  degenerate_points,       // all points coincident or collinear: no unique model
  bad_options,             // threshold/iterations/radius range/axis hint not usable
  no_model_found,          // no sample gave a model with enough support
  axis_outside_tolerance,  // the refined cylinder axis left the hinted cone
};

[[nodiscard]] std::string_view to_string(FitError error);

// Positions as double vectors, in cloud order (NaN points included).
[[nodiscard]] std::vector<Eigen::Vector3d> positions_of(const PointCloud& cloud);
// Only the points whose three coordinates are finite (no-echo points of organised clouds are NaN).
[[nodiscard]] std::vector<Eigen::Vector3d> finite_positions(const PointCloud& cloud);

// Plane normal . x = offset_m, unit normal oriented so that offset_m >= 0: offset_m is the
// distance of the origin (the scanner, in the scanner frame) from the plane.
struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_m = 0.0;
  std::size_t inlier_count = 0;
  double rms_m = 0.0;                // RMS point-to-plane distance of the inliers
  std::vector<std::size_t> inliers;  // indices into the input, ascending
};

struct PlaneRansacOptions {
  double inlier_distance_m = 0.005;
  std::uint32_t iterations = 500;
  std::uint64_t seed = 1;
};

// 3-point RANSAC (MSAC scoring), then the least-squares plane of the inliers (smallest singular
// vector of their centred scatter), inliers re-collected and refined twice.
[[nodiscard]] Expected<PlaneFit, FitError> fit_plane_ransac(std::span<const Eigen::Vector3d> points,
                                                            const PlaneRansacOptions& options = {});

[[nodiscard]] double distance_to_plane(const PlaneFit& plane, const Eigen::Vector3d& point);

// The axis should lie within max_angle_rad of direction (either sense).
struct AxisHint {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  double max_angle_rad = 0.1;
};

struct CylinderRansacOptions {
  double inlier_distance_m = 0.004;
  std::uint32_t iterations = 1000;
  std::uint64_t seed = 1;
  // With a hint, samples are 3 points on a circle about the hinted direction; without, samples
  // are 2 points whose local normals (PCA within normal_radius_m) give the axis.
  std::optional<AxisHint> axis_hint;
  double min_radius_m = 0.01;
  double max_radius_m = 1.0;
  double normal_radius_m = 0.03;
};

struct CylinderFit {
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();  // middle of the inliers' extent on the axis
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  // unit
  double radius_m = 0.0;
  double length_m = 0.0;  // max - min of the inliers' projections on the axis
  std::size_t inlier_count = 0;
  double rms_m = 0.0;  // RMS radial residual of the inliers
  std::vector<std::size_t> inliers;  // indices into the input, ascending
};

// RANSAC (MSAC scoring) then Levenberg-Marquardt on axis point, direction and radius over the
// inliers, inliers re-collected and refined three times.
[[nodiscard]] Expected<CylinderFit, FitError> fit_cylinder_ransac(
    std::span<const Eigen::Vector3d> points, const CylinderRansacOptions& options = {});

// Signed distance from the cylinder surface (positive outside), ignoring the ends.
[[nodiscard]] double distance_to_cylinder_surface(const CylinderFit& cylinder, const Eigen::Vector3d& point);

// Segmentation: remove the large planes (floor, walls), keep what lies within the seed region,
// fit the cylinder there.
struct SeedRegion {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius_m = 1.0;
};

struct CylinderSegmentationOptions {
  PlaneRansacOptions plane;
  std::size_t max_planes = 3;
  std::size_t min_plane_inliers = 1000;  // smaller planes stay (they may be the cylinder's side)
  SeedRegion seed_region;
  CylinderRansacOptions cylinder;
};

struct CylinderSegmentation {
  std::vector<PlaneFit> planes;  // in removal order; inlier indices refer to the input
  CylinderFit cylinder;          // inlier indices refer to the input
  std::size_t candidate_count = 0;  // points left in the seed region after plane removal
};

[[nodiscard]] Expected<CylinderSegmentation, FitError> segment_cylinder(
    std::span<const Eigen::Vector3d> points, const CylinderSegmentationOptions& options);

}  // namespace ldoem::cloud
