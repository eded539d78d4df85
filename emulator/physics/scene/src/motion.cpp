#include "ldoem/scene/motion.hpp"

#include "ldoem/scene/scene.hpp"

#include <algorithm>
#include <cmath>

namespace ldoem::scene {
namespace {

Eigen::Quaterniond spin(const Eigen::Vector3d& angular_velocity_rad_s, double t_s) {
  const double rate = angular_velocity_rad_s.norm();
  if (rate == 0.0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(rate * t_s, angular_velocity_rad_s / rate));
}

// Catmull-Rom tangent at waypoint i for non-uniform times; one-sided at the ends.
Eigen::Vector3d tangent(const std::vector<Waypoint>& points, std::size_t i) {
  const std::size_t last = points.size() - 1;
  const std::size_t before = i == 0 ? 0 : i - 1;
  const std::size_t after = i == last ? last : i + 1;
  return (points[after].position_m - points[before].position_m) / (points[after].t_s - points[before].t_s);
}

// Index of the segment [t_i, t_i+1] that holds t (t inside [t_first, t_last]).
std::size_t segment_of(const std::vector<Waypoint>& points, double t_s) {
  const auto it = std::upper_bound(points.begin(), points.end(), t_s,
                                   [](double t, const Waypoint& w) { return t < w.t_s; });
  const auto index = static_cast<std::size_t>(it - points.begin());
  return std::clamp<std::size_t>(index == 0 ? 0 : index - 1, 0, points.size() - 2);
}

// Waypoint time after looping (or holding): a time inside [t_first, t_last].
double path_time(const Waypoints& path, double t_s) {
  const double first = path.points.front().t_s;
  const double last = path.points.back().t_s;
  if (t_s <= first) return first;
  if (t_s <= last) return t_s;
  if (!path.loop) return last;
  return first + std::fmod(t_s - first, last - first);
}

Pose waypoint_pose(const Waypoints& path, double t_s) {
  const std::vector<Waypoint>& points = path.points;
  const double t = path_time(path, t_s);
  const std::size_t i = segment_of(points, t);
  const Waypoint& a = points[i];
  const Waypoint& b = points[i + 1];
  const double h = b.t_s - a.t_s;
  const double s = std::clamp((t - a.t_s) / h, 0.0, 1.0);
  Pose pose;
  pose.orientation = a.orientation.slerp(s, b.orientation);
  if (path.interpolation == Interpolation::linear) {
    pose.position_m = a.position_m + s * (b.position_m - a.position_m);
    return pose;
  }
  const double s2 = s * s;
  const double s3 = s2 * s;
  pose.position_m = (2 * s3 - 3 * s2 + 1) * a.position_m + (s3 - 2 * s2 + s) * h * tangent(points, i) +
                    (-2 * s3 + 3 * s2) * b.position_m + (s3 - s2) * h * tangent(points, i + 1);
  return pose;
}

struct BoundsBuilder {
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(-INFINITY);
  void add(const Eigen::Vector3d& p) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
};

// Adds the hull of every segment overlapping [a, b] (times inside [t_first, t_last]).
void add_segments(const Waypoints& path, double a, double b, BoundsBuilder& bounds) {
  const std::vector<Waypoint>& points = path.points;
  for (std::size_t i = segment_of(points, a); i + 1 < points.size() && points[i].t_s <= b; ++i) {
    const Waypoint& p = points[i];
    const Waypoint& q = points[i + 1];
    bounds.add(p.position_m);
    bounds.add(q.position_m);
    if (path.interpolation == Interpolation::cubic) {  // Bezier control points of the Hermite segment
      const double h = q.t_s - p.t_s;
      bounds.add(p.position_m + h / 3.0 * tangent(points, i));
      bounds.add(q.position_m - h / 3.0 * tangent(points, i + 1));
    }
  }
}

PathBounds waypoint_bounds(const Waypoints& path, double t0_s, double t1_s) {
  BoundsBuilder bounds;
  const double first = path.points.front().t_s;
  const double last = path.points.back().t_s;
  const double period = last - first;
  if (t0_s < first) bounds.add(path.points.front().position_m);
  const double start = std::max(t0_s, first);
  if (t1_s >= first) {
    if (!path.loop) {
      if (t1_s > last) bounds.add(path.points.back().position_m);
      if (start <= last) add_segments(path, start, std::min(t1_s, last), bounds);
    } else if (t1_s - start >= period) {
      add_segments(path, first, last, bounds);
    } else {
      const double a = path_time(path, start);
      const double b = a + (t1_s - start);
      add_segments(path, a, std::min(b, last), bounds);
      if (b > last) add_segments(path, first, first + (b - last), bounds);
    }
  }
  return {bounds.lower, bounds.upper};
}

}  // namespace

Pose pose_at(const Motion& motion, const Pose& start, double t_s) {
  if (const auto* velocity = std::get_if<ConstantVelocity>(&motion)) {
    Pose pose;
    pose.position_m = start.position_m + t_s * velocity->linear_velocity_mps;
    pose.orientation = spin(velocity->angular_velocity_rad_s, t_s) * start.orientation;
    return pose;
  }
  return waypoint_pose(std::get<Waypoints>(motion), t_s);
}

bool keeps_orientation(const Motion& motion) {
  if (const auto* velocity = std::get_if<ConstantVelocity>(&motion)) {
    return velocity->angular_velocity_rad_s.isZero(0.0);
  }
  const auto& points = std::get<Waypoints>(motion).points;
  return std::all_of(points.begin(), points.end(), [&](const Waypoint& w) {
    return w.orientation.coeffs() == points.front().orientation.coeffs();
  });
}

PathBounds path_bounds(const Motion& motion, const Pose& start, double t0_s, double t1_s) {
  if (const auto* velocity = std::get_if<ConstantVelocity>(&motion)) {
    const Eigen::Vector3d a = start.position_m + t0_s * velocity->linear_velocity_mps;
    const Eigen::Vector3d b = start.position_m + t1_s * velocity->linear_velocity_mps;
    return {a.cwiseMin(b), a.cwiseMax(b)};
  }
  return waypoint_bounds(std::get<Waypoints>(motion), t0_s, t1_s);
}

}  // namespace ldoem::scene
