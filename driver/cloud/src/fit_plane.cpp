#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "fit_support.hpp"

namespace ldoem::cloud {
namespace {

struct PlaneModel {
  Eigen::Vector3d normal;
  double offset_m;
};

double plane_residual(const PlaneModel& model, const Eigen::Vector3d& point) {
  return model.normal.dot(point) - model.offset_m;
}

std::optional<PlaneModel> plane_through(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d normal = ab.cross(ac);
  // Relative test: three nearly collinear points give no usable normal at any scale.
  if (!(normal.norm() > 1e-9 * ab.norm() * ac.norm())) return std::nullopt;
  const Eigen::Vector3d unit = normal.normalized();
  return PlaneModel{unit, unit.dot(a)};
}

double total_cost(const PlaneModel& model, std::span<const Eigen::Vector3d> points, double threshold) {
  double cost = 0.0;
  for (const Eigen::Vector3d& point : points) cost += detail::msac_cost(plane_residual(model, point), threshold);
  return cost;
}

std::vector<std::size_t> collect_inliers(const PlaneModel& model, std::span<const Eigen::Vector3d> points,
                                         double threshold) {
  std::vector<std::size_t> inliers;
  for (std::size_t index = 0; index < points.size(); ++index) {
    if (std::abs(plane_residual(model, points[index])) <= threshold) inliers.push_back(index);
  }
  return inliers;
}

// Least-squares plane: through the centroid, normal = the right singular vector of the centred
// points with the smallest singular value (the same as of their 3x3 scatter matrix).
std::optional<PlaneModel> least_squares_plane(std::span<const Eigen::Vector3d> points,
                                              const std::vector<std::size_t>& inliers) {
  if (inliers.size() < 3) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t index : inliers) centroid += points[index];
  centroid /= static_cast<double>(inliers.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t index : inliers) {
    const Eigen::Vector3d centred = points[index] - centroid;
    scatter += centred * centred.transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter, Eigen::ComputeFullV);
  const Eigen::Vector3d normal = svd.matrixV().col(2).normalized();
  return PlaneModel{normal, normal.dot(centroid)};
}

std::optional<PlaneModel> best_sampled_plane(std::span<const Eigen::Vector3d> points,
                                             const PlaneRansacOptions& options) {
  detail::SampleGenerator generator(options.seed);
  std::optional<PlaneModel> best;
  double best_cost = 0.0;
  for (std::uint32_t iteration = 0; iteration < options.iterations; ++iteration) {
    const auto sample = detail::distinct_sample<3>(generator, points.size());
    const std::optional<PlaneModel> model = plane_through(points[sample[0]], points[sample[1]], points[sample[2]]);
    if (!model) continue;
    const double cost = total_cost(*model, points, options.inlier_distance_m);
    if (!best || cost < best_cost) {
      best = model;
      best_cost = cost;
    }
  }
  return best;
}

}  // namespace

double distance_to_plane(const PlaneFit& plane, const Eigen::Vector3d& point) {
  return plane.normal.dot(point) - plane.offset_m;
}

Expected<PlaneFit, FitError> fit_plane_ransac(std::span<const Eigen::Vector3d> points,
                                              const PlaneRansacOptions& options) {
  if (!(options.inlier_distance_m > 0.0) || options.iterations == 0) {
    return base::Unexpected(FitError::bad_options);
  }
  if (const std::optional<FitError> error = detail::check_points(points, 3)) {
    return base::Unexpected(*error);
  }
  std::optional<PlaneModel> model = best_sampled_plane(points, options);
  if (!model) return base::Unexpected(FitError::no_model_found);

  std::vector<std::size_t> inliers = collect_inliers(*model, points, options.inlier_distance_m);
  constexpr int refinement_rounds = 2;
  for (int round = 0; round < refinement_rounds; ++round) {
    const std::optional<PlaneModel> refined = least_squares_plane(points, inliers);
    if (!refined) return base::Unexpected(FitError::no_model_found);
    model = refined;
    inliers = collect_inliers(*model, points, options.inlier_distance_m);
  }
  if (inliers.size() < 3) return base::Unexpected(FitError::no_model_found);

  PlaneFit fit;
  fit.normal = model->normal;
  fit.offset_m = model->offset_m;
  if (fit.offset_m < 0.0) {
    fit.normal = -fit.normal;
    fit.offset_m = -fit.offset_m;
  }
  double squares = 0.0;
  for (std::size_t index : inliers) squares += std::pow(distance_to_plane(fit, points[index]), 2);
  fit.rms_m = std::sqrt(squares / static_cast<double>(inliers.size()));
  fit.inlier_count = inliers.size();
  fit.inliers = std::move(inliers);
  return fit;
}

}  // namespace ldoem::cloud
