// The scene's solids as ODE geoms: one geom per Scene::objects entry, same index, in one space
// of one world (the world is there for the motor_dynamics hinge, D9). Owns every ODE handle
// (RAII); ODE itself is initialised once per process (dInitODE2) and never closed.
#pragma once

#include "ldoem/scene/scene.hpp"

#include <ode/ode.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace ldoem::raycast {

// Calls dInitODE2 once per process and dAllocateODEDataForThread once per calling thread
// (ODE needs per-thread collision data for trimeshes). Cheap after the first call.
void ensure_ode_ready_for_this_thread();

class OdeWorld {
 public:
  explicit OdeWorld(const scene::Scene& scene);
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
  struct TriMeshBuffers;  // vertex and index arrays ODE points into

  dGeomID create_geom(const scene::SceneObject& object);

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  std::vector<scene::SceneObject> objects_;
  std::vector<dGeomID> geoms_;
  struct BoundingSphere {
    Eigen::Vector3d centre_m;
    double radius_m;
  };
  std::vector<BoundingSphere> bounds_;
  std::vector<std::unique_ptr<TriMeshBuffers>> meshes_;
};

}  // namespace ldoem::raycast
