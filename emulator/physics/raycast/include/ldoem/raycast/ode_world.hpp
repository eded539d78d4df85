// The scene's solids as ODE geoms: one geom per Scene::objects entry, same index, in one space
// of one world (the world is there for the motor_dynamics hinge, D9). Owns every ODE handle
// (RAII); ODE itself is initialised once per process (dInitODE2) and never closed.
#pragma once

#include "ldoem/scene/scene.hpp"

#include <ode/ode.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace ldoem::raycast {

namespace detail {
class MeshIndex;  // mesh_index.hpp (internal)
}

// Calls dInitODE2 once per process and dAllocateODEDataForThread once per calling thread
// (ODE needs per-thread collision data for trimeshes). Cheap after the first call.
void ensure_ode_ready_for_this_thread();

// A mesh's ODE trimesh data: its vertex and index arrays and the OPCODE tree built over them,
// the costly part of a mesh's geom (about 0.2 s for scenes/meshes/large-rock.obj). Immutable once
// built and shared by every OdeWorld holding the mesh, so a caster rebuilt after add-object or
// remove-object does not build it again; add-object builds it on its import worker (issue 27),
// and only the cheap geom is made on the loop's thread. It also holds the mesh's Embree index for
// MovingRayCaster (issue 26: moving meshes are answered as the static caster answers meshes,
// not through the OPCODE tree), built with it for the same reason.
class TriMeshData {
 public:
  // Any thread may build one (it calls dInitODE2 once per process, nothing per thread).
  // with_moving_index: also the Embree index MovingRayCaster needs (a static world's meshes,
  // which OdeWorld builds for itself, go without it).
  static std::shared_ptr<const TriMeshData> build(const scene::Mesh& mesh, bool with_moving_index = true);
  ~TriMeshData();
  TriMeshData(const TriMeshData&) = delete;
  TriMeshData& operator=(const TriMeshData&) = delete;

  dTriMeshDataID data() const { return data_; }
  const std::shared_ptr<const detail::MeshIndex>& index() const { return index_; }  // may be null
  std::size_t triangle_count() const { return indices_.size() / 3; }
  // How many the calling thread has built: the daemon counts those its event loop built
  // (query-status mesh_trees_built_on_loop), tests that a rebuild took the prepared one.
  static std::uint64_t built_on_this_thread();

 private:
  TriMeshData() = default;
  std::vector<float> vertices_;     // x, y, z per vertex, object frame
  std::vector<dTriIndex> indices_;  // 3 per triangle
  dTriMeshDataID data_ = nullptr;
  std::shared_ptr<const detail::MeshIndex> index_;
};

class OdeWorld {
 public:
  // meshes[i], when given and not null, is object i's trimesh data, built beforehand (its mesh
  // must be object i's); the others are built here.
  explicit OdeWorld(const scene::Scene& scene, std::vector<std::shared_ptr<const TriMeshData>> meshes = {});
  ~OdeWorld();
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  dWorldID world() const { return world_; }
  dSpaceID space() const { return space_; }

  std::size_t object_count() const { return objects_.size(); }
  const scene::SceneObject& object(std::size_t index) const { return objects_[index]; }
  dGeomID geom(std::size_t index) const { return geoms_[index]; }
  bool is_plane(std::size_t index) const;
  bool is_mesh(std::size_t index) const;
  // A sphere around the geom's AABB (radius infinite for planes), for cheap culling.
  const Eigen::Vector3d& bounding_centre_m(std::size_t index) const { return bounds_[index].centre_m; }
  double bounding_radius_m(std::size_t index) const { return bounds_[index].radius_m; }

 private:
  dGeomID create_geom(const scene::SceneObject& object, std::shared_ptr<const TriMeshData> mesh);

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  std::vector<scene::SceneObject> objects_;
  std::vector<dGeomID> geoms_;
  struct BoundingSphere {
    Eigen::Vector3d centre_m;
    double radius_m;
  };
  std::vector<BoundingSphere> bounds_;
  std::vector<std::shared_ptr<const TriMeshData>> meshes_;  // what the trimesh geoms point into
};

}  // namespace ldoem::raycast
