#include "cases.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace ldoem::oracle {
namespace {

using Eigen::Vector3d;

// Reads the case's choices; past the end every read is zero, so any input is a case.
class Bytes {
 public:
  explicit Bytes(std::span<const std::uint8_t> b) : bytes_(b) {}
  std::uint8_t u8() { return at_ < bytes_.size() ? bytes_[at_++] : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = v << 8 | u8();
    return v;
  }
  double unit() { return u32() * 0x1p-32; }   // [0, 1)
  double signed_unit() { return 2.0 * unit() - 1.0; }
  double f64() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = v << 8 | u8();
    return std::bit_cast<double>(v);
  }
  float f32() { return std::bit_cast<float>(u32()); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

// C++ leaves the order in which a call's arguments are evaluated unspecified: g++ evaluates them
// last to first, clang (the asan preset) first to last, so `Vector3d(draw(), draw(), draw())`
// decoded one case two ways. Every draw of several numbers for one call goes through here, in
// the order g++ used when the committed cases (the regression tests' hexes, the seed corpus)
// were recorded: the last coordinate first.
template <typename Draw>
Vector3d drawn_last_first(Draw draw) {
  const double z = draw();
  const double y = draw();
  const double x = draw();
  return Vector3d(x, y, z);
}

double sane(double x, double lo, double hi, double fallback) {
  return std::isfinite(x) && x >= lo && x <= hi ? x : fallback;
}

Vector3d unit_vector(Bytes& in) {
  const Vector3d v = drawn_last_first([&] { return in.signed_unit(); });
  return v.norm() > 1e-3 ? Vector3d(v.normalized()) : Vector3d::UnitX();
}

Eigen::Quaterniond orientation(Bytes& in) {
  switch (in.u8() % 4) {
    case 0: return Eigen::Quaterniond::Identity();
    case 1: return Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitZ()));  // axes swapped
    default: {
      const double qz = in.signed_unit();  // last first, as drawn_last_first
      const double qy = in.signed_unit();
      const double qx = in.signed_unit();
      const double qw = in.signed_unit();
      Eigen::Quaterniond q(qw, qx, qy, qz);
      return q.norm() > 1e-3 ? q.normalized() : Eigen::Quaterniond::Identity();
    }
  }
}

// A few triangles of size ~s: random, a quad split along its diagonal, a closed tetrahedron,
// slivers and degenerate ones.
scene::Mesh mesh(Bytes& in, double s) {
  scene::Mesh m;
  m.path = "generated";
  const auto vertex = [&](const Vector3d& v) {
    m.vertices_m.push_back(v.cast<float>());
    return static_cast<std::uint32_t>(m.vertices_m.size() - 1);
  };
  const Vector3d a = s * drawn_last_first([&] { return in.signed_unit(); });
  const Vector3d b = s * drawn_last_first([&] { return in.signed_unit(); });
  const Vector3d c = s * drawn_last_first([&] { return in.signed_unit(); });
  switch (in.u8() % 5) {
    case 0: {  // quad: two triangles sharing the diagonal a-c
      const std::uint32_t i = vertex(a), j = vertex(b), k = vertex(c), l = vertex(a + c - b);
      m.triangles = {{i, j, k}, {i, k, l}};
      break;
    }
    case 1: {  // closed tetrahedron: rays through shared edges and vertices
      const std::uint32_t i = vertex(a), j = vertex(b), k = vertex(c), l = vertex(s * unit_vector(in));
      m.triangles = {{i, j, k}, {i, l, j}, {j, l, k}, {k, l, i}};
      break;
    }
    case 2: {  // a sliver: c almost on the segment a-b
      const double lambda = in.unit(), lift = std::pow(10.0, -7.0 * in.unit());
      const std::uint32_t i = vertex(a), j = vertex(b), k = vertex(a + lambda * (b - a) + lift * s * unit_vector(in));
      m.triangles = {{i, j, k}};
      break;
    }
    case 3: {  // degenerate: a repeated vertex or three collinear ones, beside a good triangle
      const std::uint32_t i = vertex(a), j = vertex(b), k = vertex(c), l = vertex(0.5 * (a + b));
      m.triangles = {{i, j, k}, {i, i, j}, {i, l, j}};
      break;
    }
    default: {
      const int n = 1 + in.u8() % 6;
      for (int t = 0; t < n; ++t) {
        const std::uint32_t i = vertex(s * drawn_last_first([&] { return in.signed_unit(); }));
        const std::uint32_t j = vertex(s * drawn_last_first([&] { return in.signed_unit(); }));
        const std::uint32_t k = vertex(s * drawn_last_first([&] { return in.signed_unit(); }));
        m.triangles.push_back({i, j, k});
      }
    }
  }
  return m;
}

scene::SceneObject generated_object(Bytes& in, const Vector3d& centre, double s, const std::vector<scene::SceneObject>& earlier) {
  // A copy of an earlier object, in the same place or nudged: coincident and nearly coincident faces.
  if (!earlier.empty() && in.u8() % 4 == 0) {
    scene::SceneObject copy = earlier[in.u8() % earlier.size()];
    switch (in.u8() % 3) {
      case 0: break;
      case 1: copy.pose.position_m.x() = std::nextafter(copy.pose.position_m.x(), INFINITY); break;
      default: copy.pose.position_m += 1e-12 * s * unit_vector(in);
    }
    if (auto* plane = std::get_if<scene::Plane>(&copy.shape); plane && in.u8() % 2) plane->offset_m = std::nextafter(plane->offset_m, INFINITY);
    return copy;
  }
  scene::SceneObject o;
  o.pose.position_m = centre + 2.0 * s * drawn_last_first([&] { return in.signed_unit(); });
  o.pose.orientation = orientation(in);
  const auto size = [&] {
    const double x = s * (0.05 + 2.0 * in.unit());
    return in.u8() % 8 == 0 ? 1e-6 * x : x;  // now and then a sliver of a solid
  };
  switch (in.u8() % 6) {
    case 0: {
      const Vector3d n = in.u8() % 2 ? Vector3d::Unit(in.u8() % 3) : unit_vector(in);
      o.shape = scene::Plane{n, n.dot(centre) + s * in.signed_unit()};
      break;
    }
    case 1: o.shape = scene::Box{drawn_last_first(size)}; break;
    case 2: o.shape = scene::Sphere{size()}; break;
    case 3: o.shape = scene::Cylinder{size(), size()}; break;
    case 4: o.shape = scene::Capsule{size(), size()}; break;
    default: o.shape = mesh(in, s);
  }
  return o;
}

scene::SceneObject explicit_object(Bytes& in) {
  scene::SceneObject o;
  const int kind = in.u8() % 6;
  // Scenes give orientations as angles in degrees: a quaternion component below 1e-12 (a
  // rotation by 1e-61 rad, say) is none; subnormal positions are 0. Such inputs are outside
  // the loader's domain and drove CORE::Expr into numbers of 1e-600 (docs/numerics.md).
  const auto flush = [](double x, double tiny) { return std::abs(x) < tiny ? 0.0 : x; };
  for (int i = 0; i < 3; ++i) o.pose.position_m[i] = flush(sane(in.f64(), -1e7, 1e7, 0.0), 1e-300);
  Eigen::Quaterniond q;
  q.w() = flush(sane(in.f64(), -1, 1, 1), 1e-12);
  q.x() = flush(sane(in.f64(), -1, 1, 0), 1e-12);
  q.y() = flush(sane(in.f64(), -1, 1, 0), 1e-12);
  q.z() = flush(sane(in.f64(), -1, 1, 0), 1e-12);
  o.pose.orientation = q.norm() > 1e-3 ? q.normalized() : Eigen::Quaterniond::Identity();
  const auto size = [&] { return sane(in.f64(), 1e-7, 1e6, 1.0); };
  switch (kind) {
    case 0: {
      const double nz = sane(in.f64(), -1, 1, 1);  // last first, as drawn_last_first
      const double ny = sane(in.f64(), -1, 1, 0);
      const double nx = sane(in.f64(), -1, 1, 0);
      Vector3d n(nx, ny, nz);
      if (!(n.norm() > 1e-3)) n = Vector3d::UnitZ();
      o.shape = scene::Plane{n.normalized(), sane(in.f64(), -1e7, 1e7, 0.0)};
      break;
    }
    case 1: o.shape = scene::Box{drawn_last_first(size)}; break;
    case 2: o.shape = scene::Sphere{size()}; break;
    case 3: o.shape = scene::Cylinder{size(), size()}; break;
    case 4: o.shape = scene::Capsule{size(), size()}; break;
    default: {
      scene::Mesh m;
      m.path = "explicit";
      const int n = 1 + in.u8() % 64;
      for (int t = 0; t < n; ++t) {
        std::array<std::uint32_t, 3> tri{};
        for (auto& index : tri) {
          Eigen::Vector3f v;
          for (int i = 0; i < 3; ++i) v[i] = static_cast<float>(sane(in.f32(), -1e6, 1e6, 0.0));
          m.vertices_m.push_back(v);
          index = static_cast<std::uint32_t>(m.vertices_m.size() - 1);
        }
        m.triangles.push_back(tri);
      }
      o.shape = std::move(m);
    }
  }
  return o;
}

// A point on object `o` (world frame), its outward normal, and the kind of feature: 0 a face,
// 1 an edge or rim, 2 a vertex or tangent-prone place.
struct SurfacePoint {
  Vector3d at, normal;
};

SurfacePoint surface_point(Bytes& in, const scene::SceneObject& o, const Vector3d& centre, double s) {
  const Eigen::Matrix3d r = o.pose.orientation.toRotationMatrix();
  const Vector3d& p = o.pose.position_m;
  const int feature = in.u8() % 3;
  const auto world = [&](const Vector3d& local, const Vector3d& normal) { return SurfacePoint{p + r * local, r * normal}; };
  if (const auto* b = std::get_if<scene::Box>(&o.shape)) {
    const Vector3d h = 0.5 * b->size_m;
    Vector3d local = h.cwiseProduct(drawn_last_first([&] { return in.signed_unit(); }));
    const int axis = in.u8() % 3;
    const double side = in.u8() % 2 ? 1.0 : -1.0;
    local[axis] = side * h[axis];
    if (feature >= 1) local[(axis + 1) % 3] = (in.u8() % 2 ? 1 : -1) * h[(axis + 1) % 3];
    if (feature == 2) local[(axis + 2) % 3] = (in.u8() % 2 ? 1 : -1) * h[(axis + 2) % 3];
    return world(local, side * Vector3d::Unit(axis));
  }
  if (const auto* sp = std::get_if<scene::Sphere>(&o.shape)) {
    const Vector3d n = unit_vector(in);
    return world(sp->radius_m * n, n);
  }
  if (std::holds_alternative<scene::Cylinder>(o.shape) || std::holds_alternative<scene::Capsule>(o.shape)) {
    const bool capsule = std::holds_alternative<scene::Capsule>(o.shape);
    const double radius = capsule ? std::get<scene::Capsule>(o.shape).radius_m : std::get<scene::Cylinder>(o.shape).radius_m;
    const double half = 0.5 * (capsule ? std::get<scene::Capsule>(o.shape).length_m : std::get<scene::Cylinder>(o.shape).length_m);
    const double phi = 2 * M_PI * in.unit();
    const Vector3d radial(std::cos(phi), std::sin(phi), 0.0);
    if (feature == 0 || capsule) {
      const double z = feature == 0 ? half * in.signed_unit() : (in.u8() % 2 ? half : -half);
      return world(radius * radial + Vector3d(0, 0, z), radial);
    }
    const double z = in.u8() % 2 ? half : -half;  // the rim, or a point of a cap
    const double along = feature == 1 ? 1.0 : std::sqrt(in.unit());
    return world(along * radius * radial + Vector3d(0, 0, z), Vector3d(0, 0, z > 0 ? 1 : -1));
  }
  if (const auto* plane = std::get_if<scene::Plane>(&o.shape)) {
    const Vector3d n = plane->normal.normalized();
    Vector3d at = centre + s * drawn_last_first([&] { return in.signed_unit(); });
    at -= (n.dot(at) - plane->offset_m) * n;
    return {at, n};
  }
  const auto& m = std::get<scene::Mesh>(o.shape);
  if (m.triangles.empty()) return {p, Vector3d::UnitX()};
  const auto& t = m.triangles[in.u8() % m.triangles.size()];
  const Vector3d a = m.vertices_m[t[0]].cast<double>(), b = m.vertices_m[t[1]].cast<double>(), c = m.vertices_m[t[2]].cast<double>();
  double wb = in.unit(), wc = in.unit();
  if (wb + wc > 1) wb = 1 - wb, wc = 1 - wc;
  if (feature == 1) wc = 0;             // on the edge a-b
  if (feature == 2) wb = wc = 0;        // at vertex a
  const Vector3d n = (b - a).cross(c - a);
  return world(a + wb * (b - a) + wc * (c - a), n.norm() > 0 ? Vector3d(n.normalized()) : Vector3d::UnitZ());
}

raycast::Ray make_ray(Bytes& in, const scene::Scene& scene, const Vector3d& centre, double s, std::uint32_t housings) {
  raycast::Ray ray;
  ray.time_s = 0.0;
  const auto& target_object = scene.objects[in.u8() % scene.objects.size()];
  const SurfacePoint target = surface_point(in, target_object, centre, s);
  const double distance = s * std::pow(10.0, 3.0 * in.unit() - 1.0);
  Vector3d direction = unit_vector(in);
  switch (in.u8() % 6) {
    case 0:  // grazing: along the tangent plane, tilted by 1e-15..1e-3 rad
    case 1: {
      Vector3d tangent = direction - direction.dot(target.normal) * target.normal;
      if (!(tangent.norm() > 1e-6)) tangent = target.normal.unitOrthogonal();
      const double magnitude = std::pow(10.0, -15.0 + 12.0 * in.unit());  // the operands of * are
      const double angle = magnitude * (in.u8() % 2 ? 1 : -1);              // unsequenced too
      direction = std::cos(angle) * tangent.normalized() - std::sin(angle) * target.normal;
      break;
    }
    case 2: direction = -target.normal; break;  // head on
    default: break;                             // from anywhere
  }
  direction.normalize();
  ray.origin_m = target.at - distance * direction;
  double reach = 4.0 * distance + 100.0 * s;
  switch (in.u8() % 8) {
    case 0: {  // the origin on the surface, or a few ulps beside it
      ray.origin_m = target.at;
      const int ulps = static_cast<int>(in.u8() % 7) - 3;
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < std::abs(ulps); ++k) ray.origin_m[i] = std::nextafter(ray.origin_m[i], ulps > 0 ? INFINITY : -INFINITY);
      }
      break;
    }
    case 1: reach = (target.at - ray.origin_m).norm(); break;  // reach ends at the surface
    case 2: reach = std::nextafter((target.at - ray.origin_m).norm(), in.u8() % 2 ? INFINITY : 0.0); break;
    case 3:  // from inside a housing, which the ray ignores
      if (housings > 0) {
        const std::uint32_t h = in.u8() % housings;
        ray.origin_m = scene.objects[h].pose.position_m + 1e-3 * s * unit_vector(in);
        ray.ignored_object = h;
        direction = (target.at - ray.origin_m).normalized();
        if (!direction.allFinite()) direction = Vector3d::UnitX();
      }
      break;
    default: break;
  }
  ray.direction = direction;
  ray.max_range_m = reach > 0 ? reach : 1.0;
  return ray;
}

}  // namespace

OracleCase make_case(std::span<const std::uint8_t> bytes) {
  Bytes in(bytes);
  OracleCase c;
  const std::uint8_t header = in.u8();
  Vector3d centre = Vector3d::Zero();
  double s = 1.0;
  std::uint32_t housings = 0;
  if (header & 1) {
    const int n = 1 + in.u8() % 8;
    for (int i = 0; i < n; ++i) c.scene.objects.push_back(explicit_object(in));
    Vector3d lower = Vector3d::Constant(INFINITY), upper = -lower;
    for (const auto& o : c.scene.objects) {
      if (std::holds_alternative<scene::Plane>(o.shape)) continue;
      lower = lower.cwiseMin(o.pose.position_m);
      upper = upper.cwiseMax(o.pose.position_m);
    }
    if (lower.allFinite()) {
      centre = 0.5 * (lower + upper);
      s = std::max(1.0, 0.5 * (upper - lower).norm());
    }
  } else {
    s = std::pow(10.0, -6.0 + 11.0 * in.unit());  // 1e-6 .. 1e5 m
    if (header & 2) centre = Vector3d(1e6, -1e6, 3e5) + s * unit_vector(in);  // far from the origin
    if (header & 4) {  // scanner housings: cylinders the rays start inside
      housings = 1 + (header >> 3 & 1);
      for (std::uint32_t h = 0; h < housings; ++h) {
        scene::SceneObject housing;
        housing.shape = scene::Cylinder{0.1 * s, 0.2 * s};
        housing.pose.position_m = centre + 0.5 * s * h * Vector3d::UnitX();
        c.scene.objects.push_back(housing);
      }
    }
    const int n = 1 + in.u8() % 4;
    for (int i = 0; i < n; ++i) c.scene.objects.push_back(generated_object(in, centre, s, c.scene.objects));
  }
  const int rays = 8 + in.u8() % 57;
  for (int i = 0; i < rays; ++i) c.rays.push_back(make_ray(in, c.scene, centre, s, housings));
  return c;
}

std::vector<std::uint8_t> encode_scene(const scene::Scene& scene, std::span<const std::uint8_t> ray_bytes) {
  std::vector<std::uint8_t> out{1, static_cast<std::uint8_t>(std::max<std::size_t>(scene.objects.size(), 1) - 1)};
  const auto f64 = [&](double v) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    for (int i = 7; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
  };
  const auto f32 = [&](float v) {
    const auto bits = std::bit_cast<std::uint32_t>(v);
    for (int i = 3; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
  };
  for (const auto& o : scene.objects) {
    out.push_back(static_cast<std::uint8_t>(o.shape.index()));  // Box, Sphere, Cylinder, Capsule, Plane, Mesh
    // explicit_object's kinds: 0 plane, 1 box, 2 sphere, 3 cylinder, 4 capsule, 5 mesh
    static constexpr std::uint8_t kKind[] = {1, 2, 3, 4, 0, 5};
    out.back() = kKind[o.shape.index()];
    for (int i = 0; i < 3; ++i) f64(o.pose.position_m[i]);
    for (const double q : {o.pose.orientation.w(), o.pose.orientation.x(), o.pose.orientation.y(), o.pose.orientation.z()}) f64(q);
    if (const auto* b = std::get_if<scene::Box>(&o.shape)) for (int i = 0; i < 3; ++i) f64(b->size_m[i]);
    if (const auto* sp = std::get_if<scene::Sphere>(&o.shape)) f64(sp->radius_m);
    if (const auto* cy = std::get_if<scene::Cylinder>(&o.shape)) f64(cy->radius_m), f64(cy->length_m);
    if (const auto* ca = std::get_if<scene::Capsule>(&o.shape)) f64(ca->radius_m), f64(ca->length_m);
    if (const auto* p = std::get_if<scene::Plane>(&o.shape)) f64(p->normal.x()), f64(p->normal.y()), f64(p->normal.z()), f64(p->offset_m);
    if (const auto* m = std::get_if<scene::Mesh>(&o.shape)) {
      const std::size_t n = std::min<std::size_t>(m->triangles.size(), 64);
      out.push_back(static_cast<std::uint8_t>(std::max<std::size_t>(n, 1) - 1));
      for (std::size_t t = 0; t < n; ++t) {
        for (const std::uint32_t v : m->triangles[t]) for (int i = 0; i < 3; ++i) f32(m->vertices_m[v][i]);
      }
    }
  }
  out.insert(out.end(), ray_bytes.begin(), ray_bytes.end());
  return out;
}

}  // namespace ldoem::oracle
