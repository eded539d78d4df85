// One scanner's physics in a scene (design.md data flow): the sensor model on the shared world,
// the tilt plate with its stepper drive board, the head's spin-up model and (D9 head_dynamics
// only) its ripple, and the MeasurementSource the control unit asks. The world (geometry and
// ray caster) is built once per scene and may be shared by several plants, one per scanner.
#pragma once

#include "ldoem/base/expected.hpp"
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "ldoem/plant/scene_ports.hpp"
#include "ldoem/plant/tilt_plate.hpp"
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/scene/scene.hpp"
#include "ldoem/sensor/sensor_model.hpp"

namespace ldoem::world {
class SceneCaster;
class WorldMotion;
}

namespace ldoem::plant {

// The scene's geometry and the ray caster over it: the static ODE world with Embree, or, when
// the scene moves (D12) or is `editable` (the daemon has a control socket: objects may be added,
// removed and moved at runtime), the world::SceneCaster. A scene in which nothing moves and that
// is not editable builds none of it.
class SceneWorld {
 public:
  explicit SceneWorld(const scene::Scene& scene, bool editable = false);
  ~SceneWorld();
  const raycast::RayCaster& caster() const;
  // D12: how measurements ready a moving world; empty for a static one.
  std::optional<WorldTiming> timing();
  // D12: the moving objects, for the control socket's move-object (WorldMotion::move_object,
  // docs/dynamic-scenes.md "Runtime changes"); null when nothing in the scene moves.
  world::WorldMotion* motion();

  // The control socket's object commands (docs/dynamic-scenes.md "Runtime changes"), between
  // revolutions on the measuring thread. Each returns the device time it takes effect at, or
  // why it was refused (the world is unchanged then).
  base::Expected<double, std::string> move_object(std::string_view name, const scene::Pose& pose, double at_s,
                                                bool keep_velocity);
  // `mesh`: the object's trimesh data if built beforehand (world::SceneCaster::add_object).
  base::Expected<double, std::string> add_object(scene::SceneObject object, double at_s,
                                               std::shared_ptr<const raycast::TriMeshData> mesh = nullptr);
  base::Expected<double, std::string> remove_object(std::string_view name, double at_s);

 private:
  scene::BeamTime beam_time_;
  std::unique_ptr<raycast::OdeWorld> world_;
  std::unique_ptr<raycast::EmbreeRayCaster> caster_;
  std::unique_ptr<world::SceneCaster> moving_caster_;
};

class ScenePlant {
 public:
  // `scene` and `world` must outlive the plant. The beams pass through `own_housing` (a Scene
  // object index: the scanner's housing, which the other scanners see; issue 15).
  ScenePlant(const scene::Scene& scene, SceneWorld& world, std::optional<std::uint32_t> own_housing = std::nullopt);

  const control::HeadModel& head_model() const { return head_; }
  control::MeasurementSource& measurement() { return *measurement_; }
  StepperDriveBoard& drive_board() { return *board_; }
  const StepperDriveBoard& drive_board() const { return *board_; }
  const TiltPlate& tilt_plate() const { return *tilt_; }

  // The gpio LPT's lines before any edge (D8): the board starts from this register value.
  void set_initial_register(std::uint8_t register_value) { board_.emplace(*tilt_, register_value); }
  // The control unit's head target changed at `at` (Actions::head_target_hz); without
  // head_dynamics nothing follows it.
  void follow_head_target(SimTime at, std::uint16_t hz) {
    if (ripple_) ripple_->set_target(at, hz);
  }

 private:
  sensor::SensorModel sensor_;
  std::unique_ptr<TiltPlate> tilt_;
  std::optional<StepperDriveBoard> board_;
  SpinUpHeadModel head_;
  std::unique_ptr<motor::HeadRippleTrack> ripple_;  // D9 head_dynamics only
  std::unique_ptr<SceneMeasurement> measurement_;
};

}  // namespace ldoem::plant
