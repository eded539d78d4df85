#include "moving_bounds.hpp"

#include "ray_probe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldoem::raycast::detail {
namespace {

constexpr double kPaddingFraction = 1e-5;

OffsetBox centred(const Eigen::Vector3d& half_m) { return {-half_m, half_m}; }

}  // namespace

LocalExtent local_extent(const scene::Shape& shape) {
  OffsetBox box{};
  double radius_m = 0.0;
  if (const auto* b = std::get_if<scene::Box>(&shape)) {
    box = centred(0.5 * b->size_m);
    radius_m = 0.5 * b->size_m.norm();
  } else if (const auto* s = std::get_if<scene::Sphere>(&shape)) {
    box = centred(Eigen::Vector3d::Constant(s->radius_m));
    radius_m = s->radius_m;
  } else if (const auto* c = std::get_if<scene::Cylinder>(&shape)) {
    box = centred(Eigen::Vector3d(c->radius_m, c->radius_m, 0.5 * c->length_m));
    radius_m = std::hypot(c->radius_m, 0.5 * c->length_m);
  } else if (const auto* p = std::get_if<scene::Capsule>(&shape)) {
    box = centred(Eigen::Vector3d(p->radius_m, p->radius_m, 0.5 * p->length_m + p->radius_m));
    radius_m = p->radius_m + 0.5 * p->length_m;
  } else if (const auto* m = std::get_if<scene::Mesh>(&shape)) {
    box = {Eigen::Vector3d::Constant(INFINITY), Eigen::Vector3d::Constant(-INFINITY)};
    for (const Eigen::Vector3f& v : m->vertices_m) {
      const Eigen::Vector3d p3 = v.cast<double>();
      box.lower_m = box.lower_m.cwiseMin(p3);
      box.upper_m = box.upper_m.cwiseMax(p3);
      radius_m = std::max(radius_m, p3.norm());
    }
  }
  // Planes never move (the loader refuses it); they get an empty extent.
  return {box.lower_m, box.upper_m, radius_m};
}

OffsetBox turned_extent(const LocalExtent& extent, const Eigen::Quaterniond& orientation) {
  const Eigen::Matrix3d r = orientation.toRotationMatrix();
  const Eigen::Vector3d centre = r * (0.5 * (extent.lower_m + extent.upper_m));
  const Eigen::Vector3d half = r.cwiseAbs() * (0.5 * (extent.upper_m - extent.lower_m));
  return {centre - half, centre + half};
}

OffsetBox sphere_extent(const LocalExtent& extent) { return centred(Eigen::Vector3d::Constant(extent.radius_m)); }

OffsetBox spin_extent(const LocalExtent& extent, const Eigen::Quaterniond& orientation, const Eigen::Vector3d& axis) {
  // Turning about `axis` keeps every point's height along the axis and its distance from it, so
  // the object stays inside the cylinder that bounds both for its local box's corners (the
  // extremes of a linear and a convex function over the box are at corners).
  const Eigen::Matrix3d r = orientation.toRotationMatrix();
  double low_m = INFINITY;
  double high_m = -INFINITY;
  double radius_m = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1) != 0 ? extent.upper_m.x() : extent.lower_m.x(),
                                (corner & 2) != 0 ? extent.upper_m.y() : extent.lower_m.y(),
                                (corner & 4) != 0 ? extent.upper_m.z() : extent.lower_m.z());
    const Eigen::Vector3d p = r * local;
    const double along_m = p.dot(axis);
    low_m = std::min(low_m, along_m);
    high_m = std::max(high_m, along_m);
    radius_m = std::max(radius_m, (p - along_m * axis).norm());
  }
  radius_m = std::min(radius_m, extent.radius_m);  // no point is farther from the origin
  OffsetBox box = sphere_extent(extent);           // the cylinder's box, within the sphere's
  for (int i = 0; i < 3; ++i) {
    const double reach_m = radius_m * std::sqrt(std::max(0.0, 1.0 - axis[i] * axis[i]));
    box.lower_m[i] = std::max(box.lower_m[i], std::min(low_m * axis[i], high_m * axis[i]) - reach_m);
    box.upper_m[i] = std::min(box.upper_m[i], std::max(low_m * axis[i], high_m * axis[i]) + reach_m);
  }
  return box;
}

RTCBounds to_embree_box(const Eigen::Vector3d& lower_m, const Eigen::Vector3d& upper_m) {
  const double magnitude = std::max({1.0, lower_m.cwiseAbs().maxCoeff(), upper_m.cwiseAbs().maxCoeff()});
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(kPaddingFraction * magnitude);
  const Eigen::Vector3d lower = lower_m - pad;
  const Eigen::Vector3d upper = upper_m + pad;
  RTCBounds box{};
  box.lower_x = round_down_to_float(lower.x());
  box.lower_y = round_down_to_float(lower.y());
  box.lower_z = round_down_to_float(lower.z());
  box.upper_x = round_up_to_float(upper.x());
  box.upper_y = round_up_to_float(upper.y());
  box.upper_z = round_up_to_float(upper.z());
  return box;
}

}  // namespace ldoem::raycast::detail
