// What both casters share: checking a Ray, one ODE ray geom per thread, and turning one
// dCollide contact into a Hit with the guards of docs/scenes.md "Numerical edge cases", and the
// accurate cross product of their triangle planes, and the roundings of doubles to Embree's floats.
// Internal to ldoem_raycast.
#pragma once

#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/raycast/ray_caster.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>

namespace ldoem::raycast::detail {

// A double as Embree's float, overflowing to +-infinity rather than to an undefined value.
inline float to_float(double value) {
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  if (value > kFloatMax) return std::numeric_limits<float>::infinity();
  if (value < -kFloatMax) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(value);
}

// The float at or below / at or above `value`: boxes rounded outwards, reaches rounded up, so
// that float rounding never loses a candidate.
inline float round_down_to_float(double value) {
  const float f = to_float(value);
  return static_cast<double>(f) > value ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

inline float round_up_to_float(double value) {
  const float f = to_float(value);
  if (!(static_cast<double>(f) < value)) return f;
  // Every cast rounds its reach up: for a positive finite float (the usual case) the next one up
  // is the next bit pattern, without libm's general nextafter.
  const auto bits = std::bit_cast<std::uint32_t>(f);
  if (bits < 0x7f800000u) return std::bit_cast<float>(bits + 1u);
  return std::nextafter(f, std::numeric_limits<float>::infinity());
}

// A ray that passed the checks: finite origin, unit direction, finite positive length.
struct CheckedRay {
  Eigen::Vector3d origin_m;
  Eigen::Vector3d direction;
  double max_range_m;
  std::uint32_t ignored_object = kNoObject;  // Ray::ignored_object
};

// Origins farther out than this (any coordinate) give no hit; longer rays are shortened to it.
// The scene loader rejects numbers beyond the same limit (docs/scenes.md).
inline constexpr double kMaxCoordinate_m = 1e9;

// A direction whose squared length is this close to 1 is taken as unit as it is.
inline constexpr double kUnitSquaredLengthTolerance = 8.0 * std::numeric_limits<double>::epsilon();

// Nothing for zero-length or non-finite directions, non-finite origins, and ranges that are
// not finite and positive. A non-unit direction is normalised (ranges are in metres).
// Inline: it runs once per cast, and a call returning the ray through memory cost ~10 % of a
// cast on small scenes.
[[gnu::always_inline]] inline std::optional<CheckedRay> check_ray(const Ray& ray) {
  if (!std::isfinite(ray.max_range_m) || !(ray.max_range_m > 0.0)) return std::nullopt;
  // ODE squares coordinates; beyond this its intermediate values overflow to Inf/NaN and its
  // internal assertions abort the process. Written so that NaN and Inf fail it too.
  const Eigen::Vector3d& o = ray.origin_m;
  if (!(std::abs(o.x()) <= kMaxCoordinate_m && std::abs(o.y()) <= kMaxCoordinate_m && std::abs(o.z()) <= kMaxCoordinate_m)) {
    return std::nullopt;
  }
  const double squared_length = ray.direction.squaredNorm();
  const double max_range_m = std::min(ray.max_range_m, kMaxCoordinate_m);
  // Unit to within the rounding of computing it (a few ulps): dividing by the square root would
  // move ranges by ~1e-16 of themselves at the price of a square root and a division per cast.
  if (std::abs(squared_length - 1.0) <= kUnitSquaredLengthTolerance) return CheckedRay{o, ray.direction, max_range_m, ray.ignored_object};
  const double length = std::sqrt(squared_length);
  // Below this a direction carries no usable angle (and its square underflows). NaN or Inf
  // components give a NaN or infinite length.
  if (!(length > 1e-150) || !std::isfinite(length)) return std::nullopt;
  return CheckedRay{o, ray.direction * (1.0 / length), max_range_m, ray.ignored_object};
}

// The calling thread's ODE ray geom, aimed along `ray` (closest hit, both faces, for trimeshes).
// ODE ray geoms are mutable (dGeomRaySet), so concurrent casts need one each. One per thread
// needs no lock (a mutex-guarded pool cost about a fifth of a cast on small scenes). It is
// re-aimed by every cast, so no answer depends on which caster or thread used it before; it is
// valid until the next call on this thread and destroyed when the thread exits.
dGeomID aim_thread_probe(const CheckedRay& ray);

// One dCollide contact: range in (0, max_range], ODE's normal as given (not yet turned).
struct Contact {
  double range_m;
  Eigen::Vector3d normal;
  std::size_t object_index;
};

// The one tie-break of both casters: the nearer contact, and at exactly the same range the
// object with the lower index (coincident surfaces give the same answer whatever the order in
// which a BVH visits them).
inline bool nearer(const Contact& candidate, const Contact& best) {
  return candidate.range_m < best.range_m ||
         (candidate.range_m == best.range_m && candidate.object_index < best.object_index);
}

// dCollide(probe, geom) along `ray` (the probe must be aimed at it). Nothing for no contact, a
// non-finite range or one outside (0, max_range].
// every_contact (trimeshes): ODE's closest hit is one triangle, also one at range 0 (a ray
// leaving a face it starts on), which is no hit and hid the rest of the mesh (issue 26); with
// it, up to kMeshContacts contacts are asked for and the nearest in (0, max_range] is kept.
inline constexpr int kMeshContacts = 64;
std::optional<Contact> collide(dGeomID probe, const CheckedRay& ray, const OdeWorld& world,
                               std::size_t object_index, bool every_contact = false);

// The Hit of a contact: unit normal turned to face the ray (only the nearest contact of a cast
// needs it, so it is computed once, at the end).
Hit to_hit(const Contact& contact, const CheckedRay& ray, const OdeWorld& world);

// e1 x e2 component by component to within 1.5 ulps of each (each a * b - c * d by Kahan's
// algorithm with fused multiply-adds, where the plain expression loses everything the two
// products share). Both casters' triangle planes take their normal from it: for a sliver (edges
// 1e-7 rad apart) the plain cross product turned the normal by u / sin(angle), which moved a
// grazing ray's range by 1e-3 m (docs/numerics.md "Findings" 8 and 12).
inline Eigen::Vector3d accurate_cross(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  const auto difference_of_products = [](double a, double b, double c, double d) {
    const double cd = c * d;
    return std::fma(a, b, -cd) + std::fma(-c, d, cd);
  };
  return {difference_of_products(e1.y(), e2.z(), e1.z(), e2.y()), difference_of_products(e1.z(), e2.x(), e1.x(), e2.z()),
          difference_of_products(e1.x(), e2.y(), e1.y(), e2.x())};
}

// Hit::normal is the surface normal turned against the ray; a degenerate one becomes -direction.
Eigen::Vector3d facing_normal(const Eigen::Vector3d& normal, const Eigen::Vector3d& direction);

}  // namespace ldoem::raycast::detail
