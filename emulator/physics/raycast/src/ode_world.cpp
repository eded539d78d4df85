#include "ldoem/raycast/ode_world.hpp"

#include "mesh_index.hpp"

#include <limits>
#include <mutex>
#include <type_traits>

namespace ldoem::raycast {

static_assert(std::is_same_v<dReal, double>, "ldoem needs ODE built in double precision (dDOUBLE)");

namespace {

thread_local std::uint64_t trimesh_builds = 0;

void ensure_ode_initialised() {
  // ODE's own process-wide initialisation; it is reference counted inside ODE and we keep one
  // reference for the life of the process.
  static std::once_flag ode_initialised;
  std::call_once(ode_initialised, [] { dInitODE2(0); });
}

}  // namespace

void ensure_ode_ready_for_this_thread() {
  ensure_ode_initialised();
  thread_local bool thread_data_allocated = false;
  if (!thread_data_allocated) {
    dAllocateODEDataForThread(dAllocateMaskAll);
    thread_data_allocated = true;
  }
}

std::shared_ptr<const TriMeshData> TriMeshData::build(const scene::Mesh& mesh, bool with_moving_index) {
  // Building the data needs no per-thread ODE data (only collisions do): a worker that builds
  // one and ends leaves nothing of ODE's behind.
  ensure_ode_initialised();
  std::shared_ptr<TriMeshData> out(new TriMeshData());
  out->vertices_.reserve(mesh.vertices_m.size() * 3);
  for (const Eigen::Vector3f& v : mesh.vertices_m) out->vertices_.insert(out->vertices_.end(), {v.x(), v.y(), v.z()});
  out->indices_.reserve(mesh.triangles.size() * 3);
  for (const auto& t : mesh.triangles) out->indices_.insert(out->indices_.end(), {t[0], t[1], t[2]});
  out->data_ = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildSingle(out->data_, out->vertices_.data(), 3 * sizeof(float),
                              static_cast<int>(mesh.vertices_m.size()), out->indices_.data(),
                              static_cast<int>(out->indices_.size()), 3 * sizeof(dTriIndex));
  if (with_moving_index) out->index_ = std::make_shared<const detail::MeshIndex>(mesh);
  ++trimesh_builds;
  return out;
}

TriMeshData::~TriMeshData() {
  if (data_ != nullptr) dGeomTriMeshDataDestroy(data_);
}

std::uint64_t TriMeshData::built_on_this_thread() { return trimesh_builds; }

namespace {

void place(dGeomID geom, const scene::Pose& pose) {
  dGeomSetPosition(geom, pose.position_m.x(), pose.position_m.y(), pose.position_m.z());
  const Eigen::Quaterniond& q = pose.orientation;
  const dQuaternion wxyz{q.w(), q.x(), q.y(), q.z()};
  dGeomSetQuaternion(geom, wxyz);
}

}  // namespace

OdeWorld::OdeWorld(const scene::Scene& scene, std::vector<std::shared_ptr<const TriMeshData>> meshes)
    : objects_(scene.objects) {
  ensure_ode_ready_for_this_thread();
  world_ = dWorldCreate();
  space_ = dSimpleSpaceCreate(nullptr);
  geoms_.reserve(objects_.size());
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    dGeomID geom = create_geom(objects_[i], i < meshes.size() ? std::move(meshes[i]) : nullptr);
    dGeomSetData(geom, reinterpret_cast<void*>(i));  // object index, for space-based queries
    // Computing the AABB now leaves no lazily updated state for concurrent casts to race on.
    dReal aabb[6];
    dGeomGetAABB(geom, aabb);
    geoms_.push_back(geom);
    if (is_plane(i)) {
      bounds_.push_back({Eigen::Vector3d::Zero(), std::numeric_limits<double>::infinity()});
    } else {
      const Eigen::Vector3d lower(aabb[0], aabb[2], aabb[4]), upper(aabb[1], aabb[3], aabb[5]);
      bounds_.push_back({0.5 * (lower + upper), 0.5 * (upper - lower).norm()});
    }
  }
}

OdeWorld::~OdeWorld() {
  for (dGeomID geom : geoms_) dGeomDestroy(geom);
  meshes_.clear();  // after the trimesh geoms that point into them
  if (space_ != nullptr) dSpaceDestroy(space_);
  if (world_ != nullptr) dWorldDestroy(world_);
}

bool OdeWorld::is_plane(std::size_t index) const {
  return std::holds_alternative<scene::Plane>(objects_[index].shape);
}

bool OdeWorld::is_mesh(std::size_t index) const {
  return std::holds_alternative<scene::Mesh>(objects_[index].shape);
}

dGeomID OdeWorld::create_geom(const scene::SceneObject& object, std::shared_ptr<const TriMeshData> prepared) {
  struct Builder {
    OdeWorld& self;
    std::shared_ptr<const TriMeshData>& prepared;
    dGeomID operator()(const scene::Box& box) const {
      return dCreateBox(self.space_, box.size_m.x(), box.size_m.y(), box.size_m.z());
    }
    dGeomID operator()(const scene::Sphere& sphere) const { return dCreateSphere(self.space_, sphere.radius_m); }
    dGeomID operator()(const scene::Cylinder& c) const { return dCreateCylinder(self.space_, c.radius_m, c.length_m); }
    dGeomID operator()(const scene::Capsule& c) const { return dCreateCapsule(self.space_, c.radius_m, c.length_m); }
    dGeomID operator()(const scene::Plane& plane) const {
      return dCreatePlane(self.space_, plane.normal.x(), plane.normal.y(), plane.normal.z(), plane.offset_m);
    }
    dGeomID operator()(const scene::Mesh& mesh) const {
      if (!prepared || prepared->triangle_count() != mesh.triangles.size()) prepared = TriMeshData::build(mesh, false);
      dGeomID geom = dCreateTriMesh(self.space_, prepared->data(), nullptr, nullptr, nullptr);
      self.meshes_.push_back(std::move(prepared));
      return geom;
    }
  };
  dGeomID geom = std::visit(Builder{*this, prepared}, object.shape);
  if (!std::holds_alternative<scene::Plane>(object.shape)) place(geom, object.pose);
  return geom;
}

}  // namespace ldoem::raycast
