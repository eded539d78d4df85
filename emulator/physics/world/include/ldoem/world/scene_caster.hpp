// D12: the caster of a scene in which something moves. Static objects go to EmbreeRayCaster
// (exactly as in a static scene), moving ones to MovingRayCaster; a ray is answered by the
// nearer of the two at the ray's instant (Ray::time_s). The daemon builds this when
// Scene::moves() is true, or when it has a control socket (objects may then be added, removed
// and moved at runtime); otherwise it builds EmbreeRayCaster alone, as before D12.
//
// Runtime changes (docs/dynamic-scenes.md "Runtime changes"), each at a device time:
// - moving objects (with `motion` or `dynamics`) live in WorldMotion; an added or removed one
//   rebuilds the moving index once, at the command, and each exists only over its time span
//   (MovingRayCaster::set_presence); an added `dynamics` object joins the ODE world at a step;
// - static objects are added, removed or moved by building a new static index at the command
//   (an "epoch" that holds from its device time on); a ray uses the epoch of its instant, and
//   epochs no later ray can reach are dropped at prepare. Nothing is rebuilt per beam.
#pragma once

#include "ldoem/base/expected.hpp"
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/moving_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/world/world_motion.hpp"

#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <variant>

namespace ldoem::world {

// At most this many static epochs waiting for their time, and objects in all: a control socket
// cannot grow memory without bound.
inline constexpr std::size_t kMaxPendingEpochs = 64;
inline constexpr std::size_t kMaxRuntimeObjects = 10'000;

class SceneCaster final : public raycast::RayCaster {
 public:
  explicit SceneCaster(const scene::Scene& scene, raycast::MovingCasterOptions options = {});
  ~SceneCaster() override;

  // Before casting rays timed in [t0, t1]: steps the rigid bodies and readies the moving index
  // (the bodies are stepped as far as the index's window reaches: options.min_window_s).
  // Not thread-safe; casts are (const) between two prepare calls.
  void prepare(double t0_s, double t1_s);

  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override;

  WorldMotion& motion() { return motion_; }
  const WorldMotion& motion() const { return motion_; }

  // The control socket's commands. Not thread-safe: call them as prepare. Each returns the
  // device time it takes effect at, or the reason it refused (nothing changed then).
  // add_object and remove_object, and moves of static objects, come in device-time order: one
  // timed before such a change already made is refused. An added `dynamics` object exists from
  // its first ODE step not yet computed at or after at_s, the time returned (RigidBodies::add).
  base::Expected<double, std::string> move_object(std::string_view name, const scene::Pose& pose, double at_s,
                                                bool keep_velocity);
  // `mesh`: the object's trimesh data, built beforehand off the loop's thread (issue 27); null:
  // built here when the object is a mesh.
  base::Expected<double, std::string> add_object(scene::SceneObject object, double at_s,
                                               std::shared_ptr<const raycast::TriMeshData> mesh = nullptr);
  base::Expected<double, std::string> remove_object(std::string_view name, double at_s);

  std::size_t static_epochs() const { return epochs_.size(); }

 private:
  struct Entry {
    scene::SceneObject object;
    bool moving = false;
    bool exists = true;  // after the last change
    // A moving mesh's trimesh data, built once and reused by every rebuild of the moving index.
    std::shared_ptr<const raycast::TriMeshData> mesh;
  };
  struct StaticEpoch {
    double from_s = -INFINITY;
    std::vector<std::uint32_t> indices;  // static caster's object index -> entry (scene) index
    std::unique_ptr<raycast::OdeWorld> world;
    std::unique_ptr<raycast::EmbreeRayCaster> caster;
  };
  StaticEpoch build_epoch(double from_s) const;
  void rebuild_moving_caster();
  std::vector<std::shared_ptr<const raycast::TriMeshData>> moving_meshes() const;
  // Whether a change may be made at at_s: refused before one already made, or when too many wait.
  base::Expected<std::monostate, std::string> check_change_time(std::string_view command, double at_s) const;
  std::ptrdiff_t find_static(std::string_view name) const;

  raycast::MovingCasterOptions options_;
  std::uint64_t moves_seen_ = 0;
  double last_change_s_ = -INFINITY;
  std::vector<Entry> entries_;  // the scene's objects (their scene index), then the added ones
  std::size_t scene_objects_ = 0;
  WorldMotion motion_;
  std::deque<StaticEpoch> epochs_;  // by from_s; the first holds from -inf
  std::unique_ptr<raycast::MovingRayCaster> moving_caster_;
};

}  // namespace ldoem::world
