#include "tessellate.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace ldoem::bench {
namespace {

// A profile (radius, z) from the bottom to the top, revolved about z: a ring of `segments`
// vertices per profile point, or one vertex where the radius is 0 (a pole, closed by a fan).
TriangleSoup lathe(const std::vector<Eigen::Vector2d>& profile, int segments) {
  TriangleSoup soup;
  std::vector<std::uint32_t> ring_start;
  std::vector<bool> is_pole;
  for (const Eigen::Vector2d& point : profile) {
    ring_start.push_back(static_cast<std::uint32_t>(soup.vertices_m.size()));
    const bool pole = point.x() == 0.0;
    is_pole.push_back(pole);
    const int count = pole ? 1 : segments;
    for (int s = 0; s < count; ++s) {
      const double angle = 2.0 * std::numbers::pi * s / segments;
      soup.vertices_m.emplace_back(static_cast<float>(point.x() * std::cos(angle)),
                                   static_cast<float>(point.x() * std::sin(angle)), static_cast<float>(point.y()));
    }
  }
  const auto u = [](int s, int n) { return static_cast<std::uint32_t>(s % n); };
  for (std::size_t p = 0; p + 1 < profile.size(); ++p) {
    const std::uint32_t lower = ring_start[p];
    const std::uint32_t upper = ring_start[p + 1];
    for (int s = 0; s < segments; ++s) {
      if (is_pole[p] && is_pole[p + 1]) continue;
      if (is_pole[p]) {
        soup.triangles.push_back({lower, upper + u(s + 1, segments), upper + u(s, segments)});
      } else if (is_pole[p + 1]) {
        soup.triangles.push_back({lower + u(s, segments), lower + u(s + 1, segments), upper});
      } else {
        soup.triangles.push_back({lower + u(s, segments), lower + u(s + 1, segments), upper + u(s + 1, segments)});
        soup.triangles.push_back({lower + u(s, segments), upper + u(s + 1, segments), upper + u(s, segments)});
      }
    }
  }
  return soup;
}

// A sphere split at its equator, the halves moved apart by `length_m` (0 gives a sphere).
TriangleSoup capsule_soup(double radius_m, double length_m, int segments) {
  const int latitudes = std::max(2, segments / 2) & ~1;  // even: the equator is a profile point
  std::vector<Eigen::Vector2d> profile;
  for (int k = 0; k <= latitudes; ++k) {
    const double polar = std::numbers::pi * k / latitudes;  // 0 at the bottom pole
    const double shift = (k < latitudes / 2) ? -0.5 * length_m : (k > latitudes / 2 ? 0.5 * length_m : 0.0);
    const double r = (k == 0 || k == latitudes) ? 0.0 : radius_m * std::sin(polar);
    if (k == latitudes / 2 && length_m > 0.0) {
      profile.emplace_back(r, -0.5 * length_m);
      profile.emplace_back(r, 0.5 * length_m);
      continue;
    }
    profile.emplace_back(r, -radius_m * std::cos(polar) + shift);
  }
  return lathe(profile, segments);
}

TriangleSoup box_soup(const Eigen::Vector3d& size_m) {
  TriangleSoup soup;
  const Eigen::Vector3d h = 0.5 * size_m;
  for (int i = 0; i < 8; ++i) {
    soup.vertices_m.emplace_back(static_cast<float>((i & 1) ? h.x() : -h.x()),
                                 static_cast<float>((i & 2) ? h.y() : -h.y()),
                                 static_cast<float>((i & 4) ? h.z() : -h.z()));
  }
  // Two triangles per face; winding does not matter to the casters (no culling).
  const std::array<std::array<std::uint32_t, 4>, 6> faces{{
      {0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}}};
  for (const auto& f : faces) {
    soup.triangles.push_back({f[0], f[1], f[2]});
    soup.triangles.push_back({f[0], f[2], f[3]});
  }
  return soup;
}

TriangleSoup plane_soup(const scene::Plane& plane, double half_size_m) {
  const Eigen::Vector3d normal = plane.normal.normalized();
  const Eigen::Vector3d centre = normal * plane.offset_m;
  const Eigen::Vector3d helper = std::abs(normal.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d a = helper.cross(normal).normalized() * half_size_m;
  const Eigen::Vector3d b = normal.cross(a);
  TriangleSoup soup;
  const std::array<Eigen::Vector3d, 4> corners{centre - a - b, centre + a - b, centre + a + b, centre - a + b};
  for (const Eigen::Vector3d& corner : corners) soup.vertices_m.push_back(corner.cast<float>());
  soup.triangles = {{0, 1, 2}, {0, 2, 3}};
  return soup;
}

void place(TriangleSoup& soup, const scene::Pose& pose) {
  for (Eigen::Vector3f& v : soup.vertices_m) {
    v = (pose.position_m + pose.orientation * v.cast<double>()).cast<float>();
  }
}

}  // namespace

void TriangleSoup::append(const TriangleSoup& other, std::uint32_t object) {
  const auto base = static_cast<std::uint32_t>(vertices_m.size());
  vertices_m.insert(vertices_m.end(), other.vertices_m.begin(), other.vertices_m.end());
  for (const auto& t : other.triangles) {
    triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    object_index.push_back(object);
  }
}

TriangleSoup tessellated_cylinder(double radius_m, double length_m, int segments, int rings) {
  std::vector<Eigen::Vector2d> profile{{0.0, -0.5 * length_m}};
  for (int k = 0; k <= rings; ++k) profile.emplace_back(radius_m, -0.5 * length_m + length_m * k / rings);
  profile.emplace_back(0.0, 0.5 * length_m);
  return lathe(profile, segments);
}

CylinderResolution cylinder_resolution_for(int triangles) {
  for (const CylinderResolution r : {CylinderResolution{16, 1}, CylinderResolution{128, 3},
                                     CylinderResolution{512, 15}, CylinderResolution{2048, 63}}) {
    if (2 * r.segments * (r.rings + 1) == triangles) return r;
  }
  throw std::invalid_argument("no cylinder resolution for that triangle count");
}

scene::Mesh cylinder_mesh(double radius_m, double length_m, int segments, int rings) {
  const TriangleSoup soup = tessellated_cylinder(radius_m, length_m, segments, rings);
  scene::Mesh mesh;
  mesh.path = "generated:cylinder";
  mesh.vertices_m = soup.vertices_m;
  mesh.triangles = soup.triangles;
  return mesh;
}

TriangleSoup tessellate_object(const scene::SceneObject& object, int segments, double plane_half_size_m) {
  TriangleSoup soup = std::visit(
      [&](const auto& shape) -> TriangleSoup {
        using T = std::decay_t<decltype(shape)>;
        if constexpr (std::is_same_v<T, scene::Box>) return box_soup(shape.size_m);
        if constexpr (std::is_same_v<T, scene::Sphere>) return capsule_soup(shape.radius_m, 0.0, segments);
        if constexpr (std::is_same_v<T, scene::Capsule>) return capsule_soup(shape.radius_m, shape.length_m, segments);
        if constexpr (std::is_same_v<T, scene::Cylinder>) {
          return tessellated_cylinder(shape.radius_m, shape.length_m, segments, 1);
        }
        if constexpr (std::is_same_v<T, scene::Plane>) return plane_soup(shape, plane_half_size_m);
        if constexpr (std::is_same_v<T, scene::Mesh>) return TriangleSoup{shape.vertices_m, shape.triangles, {}};
      },
      object.shape);
  if (!std::holds_alternative<scene::Plane>(object.shape)) place(soup, object.pose);
  return soup;
}

TriangleSoup tessellate_scene(const scene::Scene& scene, int segments, double plane_half_size_m) {
  TriangleSoup all;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    all.append(tessellate_object(scene.objects[i], segments, plane_half_size_m), static_cast<std::uint32_t>(i));
  }
  return all;
}

}  // namespace ldoem::bench
