#include "exact_primitives.hpp"

#include <algorithm>
#include <stdexcept>

namespace ldoem::raycast::detail {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Below this squared sine between a ray and an axis, the ray counts as parallel to the axis:
// over the 1e9 m a ray may reach it drifts sideways by less than 1e-90 m.
constexpr double kParallelSquaredSine = 1e-200;

// The part of a ray inside a solid: [enter, leave] in metres along it, and which surface each
// end lies on (for the normal).
struct Span {
  double enter_m = -kInfinity;
  double leave_m = kInfinity;
  int enter_face = -1;
  int leave_face = -1;
  bool empty() const { return !(enter_m <= leave_m); }
};

constexpr Span kNoSpan{kInfinity, -kInfinity};

// Narrows `span` to the slab |start + t v| <= half along one axis; `face` names the axis.
// A ray parallel to the slab is inside it or nowhere.
[[gnu::always_inline]] inline void clip_to_slab(Span& span, double start, double velocity, double half, int face) {
  if (velocity == 0.0) {
    if (std::abs(start) > half) span = kNoSpan;
    return;
  }
  // One division per axis: a box costs three instead of six (1 ulp apart, far below 1e-9 m).
  const double inverse = 1.0 / velocity;
  double near_m = (-half - start) * inverse;
  double far_m = (half - start) * inverse;
  if (near_m > far_m) std::swap(near_m, far_m);
  if (near_m > span.enter_m) {
    span.enter_m = near_m;
    span.enter_face = face;
  }
  if (far_m < span.leave_m) {
    span.leave_m = far_m;
    span.leave_face = face;
  }
}

// Where a ray (start s, unit direction v, both relative to the centre) is within `radius` of
// the centre. Written around the point of closest approach, so that a small sphere far away
// keeps its size (r^2 is not lost against |s|^2).
[[gnu::always_inline]] inline Span sphere_span(const Eigen::Vector3d& s, const Eigen::Vector3d& v, double radius_m, int face) {
  Span span;
  const double closest_m = -s.dot(v);
  const Eigen::Vector3d offset = s + closest_m * v;
  const double half_chord_squared = radius_m * radius_m - offset.squaredNorm();
  if (!(half_chord_squared >= 0.0)) return kNoSpan;
  const double half_chord_m = std::sqrt(half_chord_squared);
  span.enter_m = closest_m - half_chord_m;
  span.leave_m = closest_m + half_chord_m;
  span.enter_face = span.leave_face = face;
  return span;
}

// Where a ray (local start s, local unit direction v) is within `radius` of the local z axis.
[[gnu::always_inline]] inline Span infinite_cylinder_span(const Eigen::Vector3d& s, const Eigen::Vector3d& v, double radius_m, int face) {
  Span span;
  const double squared_sine = v.x() * v.x() + v.y() * v.y();
  if (!(squared_sine > kParallelSquaredSine)) {
    if (s.x() * s.x() + s.y() * s.y() > radius_m * radius_m) return kNoSpan;
    return span;  // along the axis: inside all the way, or never
  }
  const double closest_m = -(s.x() * v.x() + s.y() * v.y()) / squared_sine;
  const double x = s.x() + closest_m * v.x();
  const double y = s.y() + closest_m * v.y();
  const double half_chord_squared = (radius_m * radius_m - (x * x + y * y)) / squared_sine;
  if (!(half_chord_squared >= 0.0)) return kNoSpan;
  const double half_chord_m = std::sqrt(half_chord_squared);
  span.enter_m = closest_m - half_chord_m;
  span.leave_m = closest_m + half_chord_m;
  span.enter_face = span.leave_face = face;
  return span;
}

// Faces of the spans below: 0..2 box axes (or a cylinder's flat caps on 2), 3 the curved side,
// 4 a capsule's rounded surface (normal from the axis segment).
constexpr int kCapFace = 2;
constexpr int kSideFace = 3;
constexpr int kRoundFace = 4;

Span local_span(const ExactPrimitive& p, const Eigen::Vector3d& s, const Eigen::Vector3d& v) {
  switch (p.kind) {
    case PrimitiveKind::aligned_box:  // the caller passed the ray unrotated
    case PrimitiveKind::box: {
      Span span;
      for (int axis = 0; axis < 3 && !span.empty(); ++axis) clip_to_slab(span, s[axis], v[axis], p.half_size_m[axis], axis);
      return span;
    }
    case PrimitiveKind::sphere:
      return sphere_span(s, v, p.radius_m, kRoundFace);
    case PrimitiveKind::cylinder: {
      Span span = infinite_cylinder_span(s, v, p.radius_m, kSideFace);
      if (!span.empty()) clip_to_slab(span, s.z(), v.z(), p.half_length_m, kCapFace);
      return span;
    }
    case PrimitiveKind::capsule: {
      // A capsule is the union of its finite cylinder and the two end balls; a ray meets a
      // convex solid in one interval, so the union's ends are the extreme ends of the parts.
      Span span = infinite_cylinder_span(s, v, p.radius_m, kRoundFace);
      if (!span.empty()) clip_to_slab(span, s.z(), v.z(), p.half_length_m, kRoundFace);
      for (const double end_m : {-p.half_length_m, p.half_length_m}) {
        const Span ball = sphere_span(s - Eigen::Vector3d(0, 0, end_m), v, p.radius_m, kRoundFace);
        if (ball.empty()) continue;
        if (span.empty()) {
          span = ball;
          continue;
        }
        span.enter_m = std::min(span.enter_m, ball.enter_m);
        span.leave_m = std::max(span.leave_m, ball.leave_m);
      }
      span.enter_face = span.leave_face = kRoundFace;
      return span;
    }
  }
  return kNoSpan;
}

// The outward-or-inward normal (to_hit turns it to face the ray) at local point `at` on `face`.
Eigen::Vector3d local_normal(const ExactPrimitive& p, const Eigen::Vector3d& at, int face) {
  switch (face) {
    case 0: return Eigen::Vector3d::UnitX();
    case 1: return Eigen::Vector3d::UnitY();
    case kCapFace: return Eigen::Vector3d::UnitZ();
    case kSideFace: return Eigen::Vector3d(at.x(), at.y(), 0.0);
    default: {
      const double axis_m = p.kind == PrimitiveKind::sphere ? 0.0 : std::clamp(at.z(), -p.half_length_m, p.half_length_m);
      return Eigen::Vector3d(at.x(), at.y(), at.z() - axis_m);
    }
  }
}

}  // namespace

ExactPrimitive exact_primitive_of(const OdeWorld& world, std::size_t object_index) {
  const dGeomID geom = world.geom(object_index);
  ExactPrimitive p;
  const dReal* position = dGeomGetPosition(geom);
  const dReal* rotation = dGeomGetRotation(geom);  // 3 rows of 4, row-major
  p.centre_m = Eigen::Vector3d(position[0], position[1], position[2]);
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) p.axes(row, column) = rotation[4 * row + column];
  }
  p.object_index = static_cast<std::uint32_t>(object_index);
  switch (dGeomGetClass(geom)) {
    case dBoxClass: {
      dVector3 lengths;
      dGeomBoxGetLengths(geom, lengths);
      // Walls and shelves usually stand square to the world: ODE's rotation is then exactly the
      // identity and the ray need not be rotated into the box's frame.
      p.kind = p.axes == Eigen::Matrix3d::Identity() ? PrimitiveKind::aligned_box : PrimitiveKind::box;
      p.half_size_m = 0.5 * Eigen::Vector3d(lengths[0], lengths[1], lengths[2]);
      break;
    }
    case dSphereClass:
      p.kind = PrimitiveKind::sphere;
      p.radius_m = dGeomSphereGetRadius(geom);
      break;
    case dCylinderClass:
    case dCapsuleClass: {
      const bool capsule = dGeomGetClass(geom) == dCapsuleClass;
      dReal radius_m = 0, length_m = 0;
      if (capsule) {
        dGeomCapsuleGetParams(geom, &radius_m, &length_m);
      } else {
        dGeomCylinderGetParams(geom, &radius_m, &length_m);
      }
      p.kind = capsule ? PrimitiveKind::capsule : PrimitiveKind::cylinder;
      p.radius_m = radius_m;
      p.half_length_m = 0.5 * length_m;
      break;
    }
    default:
      throw std::logic_error("exact_primitive_of: object " + std::to_string(object_index) + " is not a primitive");
  }
  return p;
}

ExactPlane exact_plane_of(const OdeWorld& world, std::size_t object_index) {
  dVector4 params;
  dGeomPlaneGetParams(world.geom(object_index), params);
  return ExactPlane{Eigen::Vector3d(params[0], params[1], params[2]), params[3], static_cast<std::uint32_t>(object_index)};
}

std::optional<Contact> intersect(const ExactPrimitive& primitive, const CheckedRay& ray) {
  const bool aligned = primitive.kind == PrimitiveKind::aligned_box;
  const Eigen::Vector3d start =
      aligned ? Eigen::Vector3d(ray.origin_m - primitive.centre_m) : Eigen::Vector3d(primitive.axes.transpose() * (ray.origin_m - primitive.centre_m));
  const Eigen::Vector3d velocity = aligned ? ray.direction : Eigen::Vector3d(primitive.axes.transpose() * ray.direction);
  const Span span = local_span(primitive, start, velocity);
  if (span.empty()) return std::nullopt;
  // The entry if it lies ahead, else (the ray starts inside) the exit; a surface at exactly 0
  // is no hit (docs/scenes.md).
  const bool enters = span.enter_m >= 0.0;
  const double range_m = enters ? span.enter_m : span.leave_m;
  if (!(range_m > 0.0) || !(range_m <= ray.max_range_m)) return std::nullopt;
  const Eigen::Vector3d local = local_normal(primitive, start + range_m * velocity, enters ? span.enter_face : span.leave_face);
  return Contact{range_m, aligned ? local : Eigen::Vector3d(primitive.axes * local), primitive.object_index};
}

}  // namespace ldoem::raycast::detail
