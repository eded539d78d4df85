// Triangles for shapes the emulator answers exactly: the benchmarks compare the exact casters
// against a plain Embree triangle scene of the same objects, and the accuracy report compares the
// exact cylinder against meshes of it. Vertices lie on the true surface (inscribed polygons).
#pragma once

#include <ldoem/scene/scene.hpp>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace ldoem::bench {

struct TriangleSoup {
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint32_t> object_index;  // per triangle: Scene::objects index

  void append(const TriangleSoup& other, std::uint32_t object);
};

// A closed cylinder along local z (ODE's convention), `segments` around, `rings` bands along the
// side: 2 * segments * (rings + 1) triangles (side quads split in two, caps as fans).
[[nodiscard]] TriangleSoup tessellated_cylinder(double radius_m, double length_m, int segments, int rings);

// Segment and ring counts whose cylinder has exactly `triangles` triangles, the first of the
// ladder 16/1, 128/3, 512/15, 2048/63 (64, 1024, 16384, 262144 triangles) that fits.
struct CylinderResolution {
  int segments;
  int rings;
};
[[nodiscard]] CylinderResolution cylinder_resolution_for(int triangles);

// The cylinder as a scene Mesh (local frame, metres), ready to replace a Cylinder shape.
[[nodiscard]] scene::Mesh cylinder_mesh(double radius_m, double length_m, int segments, int rings);

// One object in world coordinates: boxes 12 triangles, spheres and capsules as UV spheres of
// `segments` longitudes, cylinders `segments` around, planes as a square of plane_half_size_m,
// meshes as they are.
[[nodiscard]] TriangleSoup tessellate_object(const scene::SceneObject& object, int segments,
                                             double plane_half_size_m);

// Every object of the scene.
[[nodiscard]] TriangleSoup tessellate_scene(const scene::Scene& scene, int segments, double plane_half_size_m);

}  // namespace ldoem::bench
