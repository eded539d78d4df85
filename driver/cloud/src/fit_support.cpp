#include "fit_support.hpp"

#include <Eigen/Eigenvalues>

namespace ldoem::cloud {

std::string_view to_string(FitError error) {
  switch (error) {
    case FitError::too_few_points: return "too_few_points";
    case FitError::non_finite_point: return "non_finite_point";
    case FitError::degenerate_points: return "degenerate_points";
    case FitError::bad_options: return "bad_options";
    case FitError::no_model_found: return "no_model_found";
    case FitError::axis_outside_tolerance: return "axis_outside_tolerance";
  }
  return "unknown";
}

std::vector<Eigen::Vector3d> positions_of(const PointCloud& cloud) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(cloud.size());
  for (const Point3f& point : cloud.positions()) out.emplace_back(point.x_m, point.y_m, point.z_m);
  return out;
}

std::vector<Eigen::Vector3d> finite_positions(const PointCloud& cloud) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(cloud.size());
  for (const Point3f& point : cloud.positions()) {
    const Eigen::Vector3d position(point.x_m, point.y_m, point.z_m);
    if (position.allFinite()) out.push_back(position);
  }
  return out;
}

namespace detail {

std::optional<FitError> check_points(std::span<const Eigen::Vector3d> points, std::size_t minimum) {
  if (points.size() < minimum) return FitError::too_few_points;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : points) {
    if (!point.allFinite()) return FitError::non_finite_point;
    sum += point;
  }
  const Eigen::Vector3d centroid = sum / static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& point : points) {
    const Eigen::Vector3d centred = point - centroid;
    scatter += centred * centred.transpose();
  }
  // Eigenvalues ascending: the middle one is zero (to rounding) when the points lie on a line.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d spread = solver.eigenvalues();
  if (spread(2) <= 0.0 || spread(1) <= 1e-12 * spread(2)) return FitError::degenerate_points;
  return std::nullopt;
}

}  // namespace detail
}  // namespace ldoem::cloud
