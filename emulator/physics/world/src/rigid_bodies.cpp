#include "ldoem/world/rigid_bodies.hpp"

#include "ldoem/raycast/ode_world.hpp"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace ldoem::world {
namespace {

constexpr int kMaxContactsPerPair = 4;
// Below this approach speed a contact does not bounce (ODE bounce_vel): it settles instead of
// chattering.
constexpr double kBounceMinSpeed_mps = 0.05;
constexpr double kObstacleFriction = 0.8;

struct Material {
  double friction;
  double restitution;
};

scene::Pose body_pose(dBodyID body) {
  const dReal* p = dBodyGetPosition(body);
  const dReal* q = dBodyGetQuaternion(body);  // w, x, y, z
  scene::Pose pose;
  pose.position_m = Eigen::Vector3d(p[0], p[1], p[2]);
  pose.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  return pose;
}

void set_body_pose(dBodyID body, const scene::Pose& pose) {
  dBodySetPosition(body, pose.position_m.x(), pose.position_m.y(), pose.position_m.z());
  const Eigen::Quaterniond& o = pose.orientation;
  const dQuaternion q{o.w(), o.x(), o.y(), o.z()};
  dBodySetQuaternion(body, q);
}

// Half the body's smallest extent: the farthest it may move in one sub-step and still meet a
// wall it would otherwise jump over.
double smallest_half_size(const scene::Shape& shape) {
  if (const auto* b = std::get_if<scene::Box>(&shape)) return 0.5 * b->size_m.minCoeff();
  if (const auto* s = std::get_if<scene::Sphere>(&shape)) return s->radius_m;
  if (const auto* c = std::get_if<scene::Cylinder>(&shape)) return std::min(c->radius_m, 0.5 * c->length_m);
  if (const auto* p = std::get_if<scene::Capsule>(&shape)) return p->radius_m;
  return 0.0;
}

dMass body_mass(const scene::Shape& shape, const scene::Dynamics& dynamics) {
  dMass mass;
  dMassSetZero(&mass);
  const double density = dynamics.density_kg_m3;
  if (const auto* b = std::get_if<scene::Box>(&shape)) {
    dMassSetBox(&mass, density, b->size_m.x(), b->size_m.y(), b->size_m.z());
  } else if (const auto* s = std::get_if<scene::Sphere>(&shape)) {
    dMassSetSphere(&mass, density, s->radius_m);
  } else if (const auto* c = std::get_if<scene::Cylinder>(&shape)) {
    dMassSetCylinder(&mass, density, 3, c->radius_m, c->length_m);
  } else if (const auto* p = std::get_if<scene::Capsule>(&shape)) {
    dMassSetCapsule(&mass, density, 3, p->radius_m, p->length_m);
  }
  if (dynamics.mass_kg) dMassAdjust(&mass, *dynamics.mass_kg);
  return mass;
}

}  // namespace

struct RigidBodies::Impl {
  std::vector<std::uint32_t> scene_indices;
  double step_s;
  std::unique_ptr<raycast::OdeWorld> obstacles;  // the static objects, for contacts only
  dWorldID world = nullptr;
  dSpaceID body_space = nullptr;
  dJointGroupID contacts = nullptr;
  std::vector<dBodyID> bodies;
  std::vector<dGeomID> geoms;
  std::deque<Material> materials;  // geoms point at their entry: a deque keeps it where it is
  std::size_t added_bodies = 0;
  std::vector<double> half_sizes;
  Material obstacle_material{kObstacleFriction, 0.0};
  std::vector<bool> left;
  struct Placement {
    std::size_t body;
    scene::Pose pose;
    double at_s;
    bool keep_velocity;
    bool remove = false;
    std::optional<scene::Dynamics> birth;  // add-object: start moving with these velocities
  };
  std::vector<Placement> placements;  // pending control-socket moves
  // frames[i] holds every body's pose at step first_step + i (time = step * step_s).
  std::deque<std::vector<scene::Pose>> frames;
  std::uint64_t first_step = 0;
  std::uint64_t steps = 0;

  ~Impl() {
    if (contacts != nullptr) dJointGroupDestroy(contacts);
    for (dGeomID g : geoms) dGeomDestroy(g);
    if (body_space != nullptr) dSpaceDestroy(body_space);
    if (world != nullptr) dWorldDestroy(world);
  }

  std::vector<scene::Pose> snapshot() const {
    std::vector<scene::Pose> poses;
    poses.reserve(bodies.size());
    for (dBodyID body : bodies) poses.push_back(body_pose(body));
    return poses;
  }

  const Material& material_of(dGeomID geom) const {
    // Only body geoms carry a Material; an obstacle's geom data is its object index in the
    // obstacles' OdeWorld (raycast::OdeWorld), not a pointer.
    if (dGeomGetBody(geom) == nullptr) return obstacle_material;
    return *static_cast<const Material*>(dGeomGetData(geom));
  }

  static void near_callback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<Impl*>(data);
    dBodyID body_a = dGeomGetBody(a);
    dBodyID body_b = dGeomGetBody(b);
    if (body_a == nullptr && body_b == nullptr) return;
    dContact contact[kMaxContactsPerPair];
    const int count = dCollide(a, b, kMaxContactsPerPair, &contact[0].geom, sizeof(dContact));
    const Material& ma = self->material_of(a);
    const Material& mb = self->material_of(b);
    for (int i = 0; i < count; ++i) {
      contact[i].surface.mode = dContactBounce | dContactApprox1;
      contact[i].surface.mu = std::sqrt(ma.friction * mb.friction);
      contact[i].surface.bounce = std::max(ma.restitution, mb.restitution);
      contact[i].surface.bounce_vel = kBounceMinSpeed_mps;
      dJointID joint = dJointCreateContact(self->world, self->contacts, &contact[i]);
      dJointAttach(joint, body_a, body_b);
    }
  }

  unsigned substeps() const {
    double ratio = 0.0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (left[i] || !dBodyIsEnabled(bodies[i])) continue;
      const dReal* v = dBodyGetLinearVel(bodies[i]);
      const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      ratio = std::max(ratio, speed * step_s / (0.5 * half_sizes[i]));
    }
    return static_cast<unsigned>(std::clamp(std::ceil(ratio), 1.0, static_cast<double>(kMaxSubsteps)));
  }

  void apply_placements(double now_s) {
    for (auto it = placements.begin(); it != placements.end();) {
      if (it->at_s > now_s) {
        ++it;
        continue;
      }
      dBodyID body = bodies[it->body];
      if (it->remove) {
        left[it->body] = true;  // frozen and out of every contact, like a body that left the world
        dBodyDisable(body);
        dGeomDisable(geoms[it->body]);
        it = placements.erase(it);
        continue;
      }
      set_body_pose(body, it->pose);
      if (it->birth) {
        const Eigen::Vector3d& v = it->birth->initial_velocity_mps;
        const Eigen::Vector3d& w = it->birth->initial_angular_velocity_rad_s;
        dBodySetLinearVel(body, v.x(), v.y(), v.z());
        dBodySetAngularVel(body, w.x(), w.y(), w.z());
      } else if (!it->keep_velocity || left[it->body]) {  // a body that left the world has no velocity to keep
        dBodySetLinearVel(body, 0, 0, 0);
        dBodySetAngularVel(body, 0, 0, 0);
      }
      dBodyEnable(body);
      left[it->body] = false;
      dGeomEnable(geoms[it->body]);
      it = placements.erase(it);
    }
  }

  void step_once() {
    const unsigned n = substeps();
    const double h = step_s / n;
    for (unsigned i = 0; i < n; ++i) {
      if (obstacles) dSpaceCollide2(reinterpret_cast<dGeomID>(obstacles->space()),
                                    reinterpret_cast<dGeomID>(body_space), this, near_callback);
      dSpaceCollide(body_space, this, near_callback);
      dWorldStep(world, h);
      dJointGroupEmpty(contacts);
    }
    ++steps;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (left[i]) continue;
      const scene::Pose pose = body_pose(bodies[i]);
      if (pose.position_m.allFinite() && pose.position_m.cwiseAbs().maxCoeff() <= kWorldLimit_m) continue;
      left[i] = true;  // frozen where it was last seen inside the world
      dBodyDisable(bodies[i]);
      dGeomDisable(geoms[i]);
      set_body_pose(bodies[i], frames.back()[i]);
    }
    apply_placements(static_cast<double>(steps) * step_s);
    frames.push_back(snapshot());
  }

  // A body for `object` at its pose with its initial velocities; false (nothing made) if the
  // object has no dynamics or no body shape (the loader allows none).
  bool create_body(const scene::SceneObject& object, std::uint32_t scene_index) {
    if (!object.dynamics) return false;
    const scene::Dynamics& dynamics = *object.dynamics;
    dGeomID geom = nullptr;
    if (const auto* b = std::get_if<scene::Box>(&object.shape)) {
      geom = dCreateBox(body_space, b->size_m.x(), b->size_m.y(), b->size_m.z());
    } else if (const auto* s = std::get_if<scene::Sphere>(&object.shape)) {
      geom = dCreateSphere(body_space, s->radius_m);
    } else if (const auto* c = std::get_if<scene::Cylinder>(&object.shape)) {
      geom = dCreateCylinder(body_space, c->radius_m, c->length_m);
    } else if (const auto* p = std::get_if<scene::Capsule>(&object.shape)) {
      geom = dCreateCapsule(body_space, p->radius_m, p->length_m);
    } else {
      return false;
    }
    dBodyID body = dBodyCreate(world);
    const dMass mass = body_mass(object.shape, dynamics);
    dBodySetMass(body, &mass);
    set_body_pose(body, object.pose);
    const Eigen::Vector3d& v = dynamics.initial_velocity_mps;
    const Eigen::Vector3d& w = dynamics.initial_angular_velocity_rad_s;
    dBodySetLinearVel(body, v.x(), v.y(), v.z());
    dBodySetAngularVel(body, w.x(), w.y(), w.z());
    dGeomSetBody(geom, body);
    materials.push_back({dynamics.friction, dynamics.restitution});
    dGeomSetData(geom, &materials.back());
    bodies.push_back(body);
    geoms.push_back(geom);
    half_sizes.push_back(smallest_half_size(object.shape));
    left.push_back(false);
    scene_indices.push_back(scene_index);
    return true;
  }

  // Fractional step index of time t, clamped to the kept frames.
  double step_index(double t_s) const {
    const double last = static_cast<double>(first_step + frames.size() - 1);
    return std::clamp(t_s / step_s, static_cast<double>(first_step), last);
  }
};

RigidBodies::RigidBodies(const scene::Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  raycast::ensure_ode_ready_for_this_thread();
  impl.step_s = scene.world.world_step_s;
  scene::Scene fixed;
  for (const scene::SceneObject& object : scene.objects) {
    if (!object.moves()) fixed.objects.push_back(object);
  }
  if (!fixed.objects.empty()) impl.obstacles = std::make_unique<raycast::OdeWorld>(fixed);
  impl.world = dWorldCreate();
  const Eigen::Vector3d& g = scene.world.gravity_mps2;
  dWorldSetGravity(impl.world, g.x(), g.y(), g.z());
  dWorldSetAutoDisableFlag(impl.world, 1);
  impl.body_space = dSimpleSpaceCreate(nullptr);
  dSpaceSetCleanup(impl.body_space, 0);  // geoms are destroyed by ~Impl
  impl.contacts = dJointGroupCreate(0);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].dynamics) impl.create_body(scene.objects[i], static_cast<std::uint32_t>(i));
  }
  impl.frames.push_back(impl.snapshot());
}

RigidBodies::~RigidBodies() = default;

std::size_t RigidBodies::body_count() const { return impl_->bodies.size(); }
const std::vector<std::uint32_t>& RigidBodies::scene_indices() const { return impl_->scene_indices; }
double RigidBodies::step_s() const { return impl_->step_s; }
std::uint64_t RigidBodies::steps_taken() const { return impl_->steps; }
bool RigidBodies::left_world(std::size_t body) const { return impl_->left.at(body); }

void RigidBodies::advance(double t0_s, double t1_s) {
  Impl& impl = *impl_;
  if (impl.bodies.empty() || !std::isfinite(t1_s)) return;
  raycast::ensure_ode_ready_for_this_thread();
  // Keep one step before t0 so that t0 itself can be interpolated.
  const double keep_from = std::max(0.0, std::floor(t0_s / impl.step_s) - 1.0);
  const auto drop_before = [&] {
    while (impl.frames.size() > 2 && static_cast<double>(impl.first_step + 1) <= keep_from) {
      impl.frames.pop_front();
      ++impl.first_step;
    }
  };
  const double target = std::ceil(t1_s / impl.step_s);
  while (static_cast<double>(impl.steps) < target) {
    impl.step_once();
    drop_before();
  }
  drop_before();
}

scene::Pose RigidBodies::pose_at(std::size_t body, double t_s) const {
  const Impl& impl = *impl_;
  const double s = impl.step_index(t_s);
  const auto i = static_cast<std::size_t>(std::floor(s)) - impl.first_step;
  const std::size_t j = std::min(i + 1, impl.frames.size() - 1);
  const double f = s - std::floor(s);
  const scene::Pose& a = impl.frames[i][body];
  const scene::Pose& b = impl.frames[j][body];
  if (f == 0.0 || i == j) return a;
  scene::Pose pose;
  pose.position_m = a.position_m + f * (b.position_m - a.position_m);
  pose.orientation = a.orientation.slerp(f, b.orientation);
  return pose;
}

Eigen::Vector3d RigidBodies::position_at(std::size_t body, double t_s) const {
  const Impl& impl = *impl_;
  const double s = impl.step_index(t_s);
  const auto i = static_cast<std::size_t>(std::floor(s)) - impl.first_step;
  const std::size_t j = std::min(i + 1, impl.frames.size() - 1);
  const double f = s - std::floor(s);
  const Eigen::Vector3d& a = impl.frames[i][body].position_m;
  if (f == 0.0 || i == j) return a;
  return a + f * (impl.frames[j][body].position_m - a);
}

scene::PathBounds RigidBodies::origin_bounds(std::size_t body, double t0_s, double t1_s) const {
  const Impl& impl = *impl_;
  const auto first = static_cast<std::size_t>(std::floor(impl.step_index(t0_s))) - impl.first_step;
  const auto last = std::min(static_cast<std::size_t>(std::ceil(impl.step_index(t1_s))) - impl.first_step,
                             impl.frames.size() - 1);
  scene::PathBounds bounds{impl.frames[first][body].position_m, impl.frames[first][body].position_m};
  for (std::size_t i = first + 1; i <= last; ++i) {
    bounds.lower_m = bounds.lower_m.cwiseMin(impl.frames[i][body].position_m);
    bounds.upper_m = bounds.upper_m.cwiseMax(impl.frames[i][body].position_m);
  }
  return bounds;
}

double RigidBodies::place(std::size_t body, const scene::Pose& pose, double at_s, bool keep_velocity) {
  (void)impl_->left.at(body);  // range check
  impl_->placements.push_back({body, pose, at_s, keep_velocity, false, std::nullopt});
  return first_step_due(at_s);
}

double RigidBodies::remove(std::size_t body, double at_s) {
  (void)impl_->left.at(body);  // range check
  impl_->placements.push_back({body, scene::Pose{}, at_s, false, true, std::nullopt});
  return first_step_due(at_s);
}

double RigidBodies::add(const scene::SceneObject& object, std::uint32_t scene_index, double at_s) {
  Impl& impl = *impl_;
  if (impl.added_bodies >= kMaxAddedBodies) {
    throw std::length_error("too many bodies added (" + std::to_string(kMaxAddedBodies) + " at most)");
  }
  if (!object.dynamics || !(smallest_half_size(object.shape) > 0.0)) {
    throw std::invalid_argument("only a box, sphere, cylinder or capsule with dynamics can be a body");
  }
  raycast::ensure_ode_ready_for_this_thread();
  if (impl.bodies.empty()) {
    // advance() never stepped a world without bodies: start its steps just before at_s rather
    // than simulate an empty world from 0 (a daemon may have run for hours).
    const double start = std::max(0.0, std::floor(at_s / impl.step_s) - 1.0);
    impl.steps = impl.first_step = static_cast<std::uint64_t>(start);
    impl.frames.assign(1, {});
  }
  const std::size_t body = impl.bodies.size();
  (void)impl.create_body(object, scene_index);  // true: the shape was checked above
  ++impl.added_bodies;
  // Not there until its step: frozen, out of every contact. Kept frames get its pose.
  impl.left[body] = true;
  dBodyDisable(impl.bodies[body]);
  dGeomDisable(impl.geoms[body]);
  for (auto& frame : impl.frames) frame.push_back(object.pose);
  impl.placements.push_back({body, object.pose, at_s, false, false, *object.dynamics});
  return first_step_due(at_s);
}

double RigidBodies::first_step_due(double at_s) const {
  // apply_placements runs after step n is taken, at time n * step_s, for every at_s <= that time.
  const double h = impl_->step_s;
  double step = std::max(std::floor(at_s / h), static_cast<double>(impl_->steps + 1));
  for (int i = 0; i < 3 && step * h < at_s; ++i) step += 1.0;  // floor's rounding, at most twice
  return step * h;
}

}  // namespace ldoem::world
