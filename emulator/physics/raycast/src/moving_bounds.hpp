// Boxes for moving objects (moving_ray_caster.cpp): how far an object's surface reaches from its
// origin, and the conversion of a double box to Embree's float box, rounded outwards and padded.
// Internal to ldoem_raycast.
#pragma once

#include "ldoem/scene/scene.hpp"

#include <embree3/rtcore.h>

namespace ldoem::raycast::detail {

// The object's axis-aligned box in its own frame (relative to its origin) and the radius of a
// sphere about its origin that holds it whatever its orientation.
struct LocalExtent {
  Eigen::Vector3d lower_m;
  Eigen::Vector3d upper_m;
  double radius_m;
};

struct OffsetBox {
  Eigen::Vector3d lower_m;
  Eigen::Vector3d upper_m;
};

LocalExtent local_extent(const scene::Shape& shape);
// The world-axis box of the object turned by `orientation`, relative to its origin.
OffsetBox turned_extent(const LocalExtent& extent, const Eigen::Quaterniond& orientation);
OffsetBox sphere_extent(const LocalExtent& extent);
// The box of every orientation the object takes turning about the unit `axis` through its origin,
// from `orientation` (any one of them): the cylinder about the axis that holds it, cut to the
// sphere of sphere_extent.
OffsetBox spin_extent(const LocalExtent& extent, const Eigen::Quaterniond& orientation, const Eigen::Vector3d& axis);

// lower/upper rounded outwards to float and padded by 1e-5 of their magnitude (at least 1e-5 m)
// so that the float rounding of a ray never loses a candidate.
RTCBounds to_embree_box(const Eigen::Vector3d& lower_m, const Eigen::Vector3d& upper_m);

}  // namespace ldoem::raycast::detail
