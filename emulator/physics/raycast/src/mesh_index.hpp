// One mesh of the moving caster, answered as the static caster answers its meshes (issue 26):
// Embree's robust float triangle test on the mesh in its own frame decides which triangle the
// ray meets, and the range is recomputed in double from that triangle's plane through its
// double world vertices (the pose applied to the float vertices at query time, as
// EmbreeRayCaster and the oracle build them), so that a moving mesh holds the static caster's
// bounds (docs/numerics.md) rather than ODE's float trimesh's. Built with the mesh's
// TriMeshData (ode_world.hpp), so that a moving caster rebuilt at a runtime change builds no
// mesh's tree again. Internal to ldoem_raycast.
#pragma once

#include "ldoem/scene/scene.hpp"
#include "ray_probe.hpp"

#include <embree3/rtcore.h>

#include <optional>
#include <vector>

namespace ldoem::raycast::detail {

class MeshIndex {
 public:
  // The mesh's float vertices and triangles, in the object's frame. Any thread may build one
  // (every index lives on one process-wide Embree device). Throws std::runtime_error on an
  // Embree error.
  explicit MeshIndex(const scene::Mesh& mesh);
  ~MeshIndex();
  MeshIndex(const MeshIndex&) = delete;
  MeshIndex& operator=(const MeshIndex&) = delete;

  // The nearest triangle in (0, reach] of `ray` (world frame) with the mesh at `pose`; the
  // contact's normal is the triangle's unit world normal (not yet turned to face the ray).
  // Safe to call from Embree callbacks and from several threads at once.
  std::optional<Contact> intersect(const CheckedRay& ray, const scene::Pose& pose, double reach_m,
                                   std::size_t object_index) const;

 private:
  RTCScene scene_ = nullptr;
  std::vector<Eigen::Vector3f> vertices_m_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  Eigen::Vector3d centre_m_ = Eigen::Vector3d::Zero();  // of the vertices' bounds (object frame)
  double radius_m_ = 0.0;                                // of the sphere about it holding them
};

}  // namespace ldoem::raycast::detail
