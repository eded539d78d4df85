#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "fit_support.hpp"
#include "neighbour_grid.hpp"

namespace ldoem::cloud {
namespace {

struct CylinderModel {
  Eigen::Vector3d point;      // any point on the axis
  Eigen::Vector3d direction;  // unit
  double radius_m;
};

double radial_residual(const CylinderModel& model, const Eigen::Vector3d& point) {
  const Eigen::Vector3d offset = point - model.point;
  const Eigen::Vector3d radial = offset - offset.dot(model.direction) * model.direction;
  return radial.norm() - model.radius_m;
}

bool radius_allowed(double radius_m, const CylinderRansacOptions& options) {
  return radius_m >= options.min_radius_m && radius_m <= options.max_radius_m;
}

// Circle through three points seen along `direction` (their projections on the normal plane).
std::optional<CylinderModel> circle_about(const Eigen::Vector3d& direction, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = direction.unitOrthogonal();
  const Eigen::Vector3d v = direction.cross(u);
  // Coordinates relative to a, so the circumcentre formula does not cancel large numbers.
  const double bx = (b - a).dot(u);
  const double by = (b - a).dot(v);
  const double cx = (c - a).dot(u);
  const double cy = (c - a).dot(v);
  const double determinant = 2.0 * (bx * cy - by * cx);
  const double scale = (bx * bx + by * by) * (cx * cx + cy * cy);
  if (!(determinant * determinant > 1e-12 * scale)) return std::nullopt;  // collinear in projection
  const double b_squared = bx * bx + by * by;
  const double c_squared = cx * cx + cy * cy;
  const double centre_u = (cy * b_squared - by * c_squared) / determinant;
  const double centre_v = (bx * c_squared - cx * b_squared) / determinant;
  const Eigen::Vector3d centre = a + centre_u * u + centre_v * v;
  return CylinderModel{centre, direction, std::hypot(centre_u, centre_v)};
}

// Axis from two surface points and their normals: normals of a cylinder cross the axis at
// right angles, so the axis runs along n_i x n_j and through where the normal lines meet.
std::optional<CylinderModel> cylinder_from_normals(const Eigen::Vector3d& p_i, const Eigen::Vector3d& n_i,
                                                   const Eigen::Vector3d& p_j, const Eigen::Vector3d& n_j) {
  const Eigen::Vector3d axis = n_i.cross(n_j);
  constexpr double min_normal_sine = 0.1;  // normals closer than ~6 deg locate the axis poorly
  if (!(axis.norm() > min_normal_sine)) return std::nullopt;
  const Eigen::Vector3d direction = axis.normalized();
  const auto flatten = [&direction](const Eigen::Vector3d& p) { return Eigen::Vector3d(p - p.dot(direction) * direction); };
  const Eigen::Vector3d flat_i = flatten(p_i);
  const Eigen::Vector3d flat_j = flatten(p_j);
  Eigen::Matrix<double, 3, 2> lines;
  lines.col(0) = n_i;
  lines.col(1) = -n_j;
  const Eigen::Vector2d steps = (lines.transpose() * lines).ldlt().solve(lines.transpose() * (flat_j - flat_i));
  const Eigen::Vector3d centre = flat_i + steps(0) * n_i;
  const double radius_m = 0.5 * ((flat_i - centre).norm() + (flat_j - centre).norm());
  return CylinderModel{centre, direction, radius_m};
}

double total_cost(const CylinderModel& model, std::span<const Eigen::Vector3d> points, double threshold) {
  double cost = 0.0;
  for (const Eigen::Vector3d& point : points) cost += detail::msac_cost(radial_residual(model, point), threshold);
  return cost;
}

std::vector<std::size_t> collect_inliers(const CylinderModel& model, std::span<const Eigen::Vector3d> points,
                                         double threshold) {
  std::vector<std::size_t> inliers;
  for (std::size_t index = 0; index < points.size(); ++index) {
    if (std::abs(radial_residual(model, points[index])) <= threshold) inliers.push_back(index);
  }
  return inliers;
}

// Lazily computed local normals (free-axis sampling only looks at a few hundred points).
class NormalCache {
 public:
  NormalCache(std::span<const Eigen::Vector3d> points, double radius_m)
      : grid_(points, radius_m), state_(points.size(), State::unknown), normals_(points.size()) {}
  std::optional<Eigen::Vector3d> normal(std::size_t index) {
    if (state_[index] == State::unknown) {
      const std::optional<Eigen::Vector3d> found = grid_.normal_at(index);
      state_[index] = found ? State::known : State::none;
      if (found) normals_[index] = *found;
    }
    if (state_[index] == State::none) return std::nullopt;
    return normals_[index];
  }

 private:
  enum class State : std::uint8_t { unknown, known, none };
  detail::NeighbourGrid grid_;
  std::vector<State> state_;
  std::vector<Eigen::Vector3d> normals_;
};

std::optional<CylinderModel> best_sampled_cylinder(std::span<const Eigen::Vector3d> points,
                                                   const CylinderRansacOptions& options) {
  detail::SampleGenerator generator(options.seed);
  std::optional<NormalCache> normals;
  if (!options.axis_hint) normals.emplace(points, options.normal_radius_m);
  std::optional<CylinderModel> best;
  double best_cost = 0.0;
  for (std::uint32_t iteration = 0; iteration < options.iterations; ++iteration) {
    std::optional<CylinderModel> model;
    if (options.axis_hint) {
      const auto sample = detail::distinct_sample<3>(generator, points.size());
      model = circle_about(options.axis_hint->direction.normalized(), points[sample[0]], points[sample[1]],
                           points[sample[2]]);
    } else {
      const auto sample = detail::distinct_sample<2>(generator, points.size());
      const std::optional<Eigen::Vector3d> n_i = normals->normal(sample[0]);
      const std::optional<Eigen::Vector3d> n_j = normals->normal(sample[1]);
      if (n_i && n_j) model = cylinder_from_normals(points[sample[0]], *n_i, points[sample[1]], *n_j);
    }
    if (!model || !radius_allowed(model->radius_m, options)) continue;
    const double cost = total_cost(*model, points, options.inlier_distance_m);
    if (!best || cost < best_cost) {
      best = model;
      best_cost = cost;
    }
  }
  return best;
}

double squared_residuals(const CylinderModel& model, std::span<const Eigen::Vector3d> points,
                         const std::vector<std::size_t>& inliers) {
  double sum = 0.0;
  for (std::size_t index : inliers) sum += std::pow(radial_residual(model, points[index]), 2);
  return sum;
}

// Levenberg-Marquardt on 5 parameters: the axis point moves in the plane normal to the axis
// (moving along it changes nothing), the direction tilts by two small angles, the radius.
// Residual rho - r with rho the distance from the axis; analytic Jacobian.
CylinderModel refine_cylinder(CylinderModel model, std::span<const Eigen::Vector3d> points,
                              const std::vector<std::size_t>& inliers) {
  double damping = 1e-3;
  double cost = squared_residuals(model, points, inliers);
  constexpr int max_iterations = 50;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    const Eigen::Vector3d u = model.direction.unitOrthogonal();
    const Eigen::Vector3d v = model.direction.cross(u);
    Eigen::Matrix<double, 5, 5> normal_matrix = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> gradient = Eigen::Matrix<double, 5, 1>::Zero();
    for (std::size_t index : inliers) {
      const Eigen::Vector3d offset = points[index] - model.point;
      const double along = offset.dot(model.direction);
      const Eigen::Vector3d radial = offset - along * model.direction;
      const double rho = radial.norm();
      if (!(rho > 1e-12)) continue;  // a point on the axis has no defined radial direction
      const Eigen::Vector3d outward = radial / rho;
      Eigen::Matrix<double, 5, 1> jacobian;
      jacobian << -outward.dot(u), -outward.dot(v), -along * outward.dot(u), -along * outward.dot(v), -1.0;
      normal_matrix += jacobian * jacobian.transpose();
      gradient += jacobian * (rho - model.radius_m);
    }
    bool improved = false;
    while (!improved && damping < 1e10) {
      Eigen::Matrix<double, 5, 5> damped = normal_matrix;
      damped.diagonal() *= 1.0 + damping;
      const Eigen::Matrix<double, 5, 1> step = damped.ldlt().solve(-gradient);
      if (!step.allFinite()) break;
      CylinderModel candidate{model.point + step(0) * u + step(1) * v,
                              (model.direction + step(2) * u + step(3) * v).normalized(),
                              model.radius_m + step(4)};
      const double candidate_cost = squared_residuals(candidate, points, inliers);
      if (candidate_cost < cost) {
        const bool converged = cost - candidate_cost < 1e-12 * cost + 1e-30;
        model = candidate;
        cost = candidate_cost;
        damping = std::max(damping / 10.0, 1e-12);
        improved = true;
        if (converged) return model;
      } else {
        damping *= 10.0;
      }
    }
    if (!improved) break;
  }
  return model;
}

// Deterministic sense: along the hint, else with its largest component positive.
Eigen::Vector3d oriented(const Eigen::Vector3d& direction, const std::optional<AxisHint>& hint) {
  if (hint) return direction.dot(hint->direction) < 0.0 ? Eigen::Vector3d(-direction) : direction;
  Eigen::Index largest = 0;
  direction.cwiseAbs().maxCoeff(&largest);
  return direction(largest) < 0.0 ? Eigen::Vector3d(-direction) : direction;
}

CylinderFit describe(const CylinderModel& model, std::span<const Eigen::Vector3d> points,
                     std::vector<std::size_t> inliers, const std::optional<AxisHint>& hint) {
  CylinderFit fit;
  fit.axis_direction = oriented(model.direction, hint);
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -std::numeric_limits<double>::infinity();
  for (std::size_t index : inliers) {
    const double along = (points[index] - model.point).dot(fit.axis_direction);
    lowest = std::min(lowest, along);
    highest = std::max(highest, along);
  }
  fit.axis_point = model.point + 0.5 * (lowest + highest) * fit.axis_direction;
  fit.length_m = highest - lowest;
  fit.radius_m = model.radius_m;
  fit.rms_m = std::sqrt(squared_residuals(model, points, inliers) / static_cast<double>(inliers.size()));
  fit.inlier_count = inliers.size();
  fit.inliers = std::move(inliers);
  return fit;
}

bool options_usable(const CylinderRansacOptions& options) {
  if (!(options.inlier_distance_m > 0.0) || options.iterations == 0) return false;
  if (!(options.min_radius_m >= 0.0) || !(options.max_radius_m > options.min_radius_m)) return false;
  if (options.axis_hint) {
    const AxisHint& hint = *options.axis_hint;
    if (!hint.direction.allFinite() || !(hint.direction.norm() > 0.0) || !(hint.max_angle_rad >= 0.0)) return false;
  } else if (!(options.normal_radius_m > 0.0)) {
    return false;
  }
  return true;
}

}  // namespace

double distance_to_cylinder_surface(const CylinderFit& cylinder, const Eigen::Vector3d& point) {
  return radial_residual(CylinderModel{cylinder.axis_point, cylinder.axis_direction, cylinder.radius_m}, point);
}

Expected<CylinderFit, FitError> fit_cylinder_ransac(std::span<const Eigen::Vector3d> points,
                                                    const CylinderRansacOptions& options) {
  if (!options_usable(options)) return base::Unexpected(FitError::bad_options);
  constexpr std::size_t cylinder_parameters = 5;
  if (const std::optional<FitError> error = detail::check_points(points, cylinder_parameters)) {
    return base::Unexpected(*error);
  }
  std::optional<CylinderModel> model = best_sampled_cylinder(points, options);
  if (!model) return base::Unexpected(FitError::no_model_found);

  std::vector<std::size_t> inliers = collect_inliers(*model, points, options.inlier_distance_m);
  constexpr int refinement_rounds = 3;
  for (int round = 0; round < refinement_rounds && inliers.size() >= cylinder_parameters; ++round) {
    model = refine_cylinder(*model, points, inliers);
    inliers = collect_inliers(*model, points, options.inlier_distance_m);
  }
  if (inliers.size() < cylinder_parameters || !radius_allowed(model->radius_m, options)) {
    return base::Unexpected(FitError::no_model_found);
  }
  if (options.axis_hint) {
    const double cosine = std::abs(model->direction.dot(options.axis_hint->direction.normalized()));
    if (std::acos(std::min(1.0, cosine)) > options.axis_hint->max_angle_rad) {
      return base::Unexpected(FitError::axis_outside_tolerance);
    }
  }
  return describe(*model, points, std::move(inliers), options.axis_hint);
}

}  // namespace ldoem::cloud
