// D12 `dynamics`: real ODE bodies under the scene's gravity, with contacts against the static
// world and each other, stepped at world_step_s (dWorldStep). Poses between steps are
// interpolated (positions linearly, orientations by slerp); the error this adds is documented in
// docs/dynamic-scenes.md. Steps are computed ahead on demand (advance) and kept only as far back
// as the caller still needs them, so memory stays bounded however long the daemon runs.
//
// Hard cases handled here:
// - tunnelling: a step is cut into sub-steps so that no body moves more than half its smallest
//   half-size per sub-step (up to kMaxSubsteps), so a fast small body meets a thin wall;
// - a body farther than kWorldLimit_m from the origin has left the world: it is frozen where it
//   left and no longer simulated (left_world() says so);
// - resting bodies are auto-disabled by ODE, so a body at rest does not drift.
#pragma once

#include "ldoem/scene/scene.hpp"

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

namespace ldoem::world {

inline constexpr double kWorldLimit_m = 1.0e4;
inline constexpr unsigned kMaxSubsteps = 256;
// At most this many bodies added at runtime (add-object) in a world's life: every body is
// stepped and collided with the others at every step, so their number bounds the step's cost.
inline constexpr std::size_t kMaxAddedBodies = 256;

class RigidBodies {
 public:
  // Every object of `scene` with `dynamics` becomes a body (in scene order); every object that
  // never moves is an obstacle. Kinematic (`motion`) objects are not obstacles to bodies.
  explicit RigidBodies(const scene::Scene& scene);
  ~RigidBodies();
  RigidBodies(const RigidBodies&) = delete;
  RigidBodies& operator=(const RigidBodies&) = delete;

  std::size_t body_count() const;
  const std::vector<std::uint32_t>& scene_indices() const;  // body -> Scene::objects index
  double step_s() const;
  std::uint64_t steps_taken() const;

  // Steps until poses up to t1 are known; forgets steps before t0 (they cannot be asked for
  // again: pose_at clamps to the oldest kept step).
  void advance(double t0_s, double t1_s);

  // Interpolated between the two steps around t (clamped to the steps kept). Const, thread-safe.
  scene::Pose pose_at(std::size_t body, double t_s) const;
  // pose_at(body, t).position_m without the orientation's slerp (the casters' sphere pre-test
  // needs only the position). Same numbers as pose_at.
  Eigen::Vector3d position_at(std::size_t body, double t_s) const;
  // A box holding the body's origin over [t0, t1] (the kept steps there, and their neighbours).
  scene::PathBounds origin_bounds(std::size_t body, double t0_s, double t1_s) const;
  bool left_world(std::size_t body) const;

  // The control socket's move: at the first step at or after at_s that is not yet simulated the
  // body is placed at `pose` (a teleport: contacts do not push it there). Its velocities are
  // zeroed (at rest) unless keep_velocity, which keeps the linear and angular velocity it has at
  // that step. Returns that step's time: later than at_s when steps up to at_s were already
  // computed (bodies are stepped ahead of the beams, SceneCaster::prepare).
  double place(std::size_t body, const scene::Pose& pose, double at_s, bool keep_velocity = false);
  // The control socket's remove-object: at the first step not yet computed at or after at_s the
  // body stops (frozen, no longer colliding with the others). Returns that step's time.
  double remove(std::size_t body, double at_s);
  // The control socket's add-object of a `dynamics` object: it becomes body body_count() (the
  // value before the call; scene_indices() gives it `scene_index`) and joins the world at the first step not yet computed at or after
  // at_s, at its `pose` with its initial velocities, colliding from then on; before that it is
  // frozen at its pose and meets nothing. Returns that step's time. Throws std::invalid_argument
  // if the object has no dynamics or no body shape, std::length_error past kMaxAddedBodies.
  double add(const scene::SceneObject& object, std::uint32_t scene_index, double at_s);

 private:
  double first_step_due(double at_s) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::world
