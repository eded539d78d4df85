// Closed-form ray tests for the scene's primitives and planes, in double precision, for the
// Embree caster's hot path. They answer what ODE's dCollide answers (nearest surface at range
// >= 0 along the ray; from inside a solid, its exit surface), checked against OdeRayCaster by
// tests/raycast, but without the per-call cost of aiming an ODE ray geom and dispatching
// dCollide (about a third of a cast on the corridor, measured with callgrind).
// The geometry is read back from the ODE geoms (position, rotation, sizes), so both casters see
// the same numbers. Internal to ldoem_raycast.
#pragma once

#include "ray_probe.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

namespace ldoem::raycast::detail {

enum class PrimitiveKind : std::uint8_t { box, aligned_box, sphere, cylinder, capsule };

struct ExactPrimitive {
  Eigen::Vector3d centre_m;
  Eigen::Matrix3d axes;          // columns: the primitive's own x, y, z axes in the world
  Eigen::Vector3d half_size_m;   // box only
  double radius_m = 0.0;         // sphere, cylinder, capsule
  double half_length_m = 0.0;    // cylinder, capsule: along the own z axis
  PrimitiveKind kind = PrimitiveKind::box;
  std::uint32_t object_index = 0;
};

// An infinite plane as ODE stores it: unit normal n and offset d, n . p = d.
struct ExactPlane {
  Eigen::Vector3d normal;
  double offset_m;
  std::uint32_t object_index;
};

// The primitive geom of `object_index` (box, sphere, cylinder or capsule) as ODE holds it.
ExactPrimitive exact_primitive_of(const OdeWorld& world, std::size_t object_index);
// The plane geom of `object_index` as ODE holds it (normalised by ODE).
ExactPlane exact_plane_of(const OdeWorld& world, std::size_t object_index);

// The nearest contact in (0, max_range_m], as collide() would return it (normal not yet unit or
// turned: to_hit does that for the one contact a cast keeps).
std::optional<Contact> intersect(const ExactPrimitive& primitive, const CheckedRay& ray);

// Planes are one division: inline, they are tested on every cast.
[[gnu::always_inline]] inline std::optional<Contact> intersect(const ExactPlane& plane, const CheckedRay& ray) {
  const Eigen::Vector3d& n = plane.normal;
  const double along = n.x() * ray.direction.x() + n.y() * ray.direction.y() + n.z() * ray.direction.z();
  const double height_m = plane.offset_m - (n.x() * ray.origin_m.x() + n.y() * ray.origin_m.y() + n.z() * ray.origin_m.z());
  // Behind the origin, parallel or on the plane: no hit, decided by signs (exact) before paying
  // for the division. Half of a scan's rays leave the floor.
  if (!((height_m > 0.0 && along > 0.0) || (height_m < 0.0 && along < 0.0))) return std::nullopt;
  const double range_m = height_m / along;
  // Also rejects NaN; a range of exactly 0 (origin on the plane) is no hit, as with collide().
  if (!(range_m > 0.0) || !(range_m <= ray.max_range_m)) return std::nullopt;
  return Contact{range_m, n, plane.object_index};
}

}  // namespace ldoem::raycast::detail
