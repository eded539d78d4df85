// D12: where every moving object of a scene is, at any instant. Kinematic objects follow their
// `motion` (scene/motion.hpp); `dynamics` objects are bodies of RigidBodies. Moving objects are
// numbered in scene order ("moving index"); scene_indices() maps them back to Scene::objects.
//
// The control socket moves objects through move_object (docs/dynamic-scenes.md "Runtime changes").
#pragma once

#include "ldoem/base/expected.hpp"
#include "ldoem/raycast/moving_ray_caster.hpp"
#include "ldoem/world/rigid_bodies.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace ldoem::world {

// At most this many pending moves per object: a control socket cannot grow memory without bound.
inline constexpr std::size_t kMaxMovesPerObject = 1024;

class WorldMotion final : public raycast::MotionSource {
 public:
  explicit WorldMotion(const scene::Scene& scene);

  const std::vector<std::uint32_t>& scene_indices() const { return scene_indices_; }
  std::vector<scene::SceneObject> moving_objects() const;

  // Steps the rigid bodies so that poses in [t0, t1] are known (forgets older steps).
  void advance(double t0_s, double t1_s);

  // From device time at_s on, object `name` (its `name:` in the scene, or "object<N>") is at
  // `pose` and stays there; a `dynamics` body restarts from rest there, under gravity. Only
  // objects that move in the scene can be moved (a static object is in the static index; give it
  // `motion: {linear_velocity_mps: [0, 0, 0]}` to make it movable). Not thread-safe: call it
  // between batches of casts, as prepare. Returns the reason it refused, or nothing when done.
  [[nodiscard]] std::optional<std::string> move_object(std::string_view name, const scene::Pose& pose, double at_s);
  // The same, saying when the move takes effect (at_s for a kinematic object; a body's first
  // step not yet computed at or after at_s, RigidBodies::place). keep_velocity: a body keeps
  // the velocity it has at that step (a teleport in flight) instead of restarting from rest;
  // kinematic objects have no velocity of their own after a move (they stay at `pose`).
  [[nodiscard]] base::Expected<double, std::string> move(std::string_view name, const scene::Pose& pose, double at_s,
                                                       bool keep_velocity = false);
  // True if a moving object that has not been removed is called `name`.
  bool has(std::string_view name) const;

  // Runtime changes (SceneCaster's add_object / remove_object). add: a kinematic object (with
  // `motion`) or a `dynamics` body that exists from from_s on, hits reporting `scene_index`; it
  // becomes the last moving index. A body joins at its first step not yet computed at or after
  // from_s (RigidBodies::add); add returns the time it exists from (from_s for a kinematic
  // object). remove: the named object stops existing at at_s (a body stops at its next step,
  // RigidBodies::remove); returns the reason when there is no such object.
  double add(scene::SceneObject object, std::uint32_t scene_index, double from_s);
  [[nodiscard]] std::optional<std::string> remove(std::string_view name, double at_s);
  // When each moving object exists (for MovingRayCaster::set_presence); empty if all always do.
  std::vector<raycast::TimeSpan> presence() const;

  scene::Pose pose_at(std::size_t k, double t_s) const override;
  Eigen::Vector3d position_at(std::size_t k, double t_s) const override;
  scene::PathBounds origin_bounds(std::size_t k, double t0_s, double t1_s) const override;
  bool keeps_orientation(std::size_t k) const override;
  std::optional<Eigen::Vector3d> spin_axis(std::size_t k) const override;

  const RigidBodies& rigid_bodies() const { return bodies_; }
  // Counts accepted moves: an index prepared before a move must be rebuilt (SceneCaster does).
  std::uint64_t moves_accepted() const { return moves_accepted_; }

 private:
  struct Move {
    double at_s;
    scene::Pose pose;
  };
  struct Mover {
    std::string name;
    scene::SceneObject object;   // pose at t = 0 and motion (kinematic) or dynamics
    std::ptrdiff_t body = -1;    // RigidBodies index for dynamics objects
    std::vector<Move> moves;     // kinematic moves, sorted by at_s
    bool keeps_orientation = true;
    raycast::TimeSpan exists;    // add-object / remove-object
  };
  // The mover called `name` that has not been removed (the latest of that name), or end().
  std::vector<Mover>::iterator find(std::string_view name);

  std::vector<Mover> movers_;
  std::uint64_t moves_accepted_ = 0;
  bool changed_ = false;  // an object was added or removed: presence() is not trivial
  std::vector<std::uint32_t> scene_indices_;
  RigidBodies bodies_;
};

}  // namespace ldoem::world
