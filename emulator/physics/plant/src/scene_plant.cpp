#include "ldoem/plant/scene_plant.hpp"

#include "ldoem/motor/tilt_motor.hpp"
#include "ldoem/world/scene_caster.hpp"
#include "ldoem/world/world_motion.hpp"

namespace ldoem::plant {

SceneWorld::SceneWorld(const scene::Scene& scene, bool editable) : beam_time_(scene.world.beam_time) {
  if (scene.moves() || editable) {
    moving_caster_ = std::make_unique<world::SceneCaster>(scene);
  } else {
    world_ = std::make_unique<raycast::OdeWorld>(scene);
    caster_ = std::make_unique<raycast::EmbreeRayCaster>(*world_);
  }
}

SceneWorld::~SceneWorld() = default;

const raycast::RayCaster& SceneWorld::caster() const {
  if (moving_caster_) return *moving_caster_;
  return *caster_;
}

std::optional<WorldTiming> SceneWorld::timing() {
  if (!moving_caster_) return std::nullopt;
  return WorldTiming{[caster = moving_caster_.get()](double t0_s, double t1_s) { caster->prepare(t0_s, t1_s); },
                     beam_time_};
}

world::WorldMotion* SceneWorld::motion() { return moving_caster_ ? &moving_caster_->motion() : nullptr; }

base::Expected<double, std::string> SceneWorld::move_object(std::string_view name, const scene::Pose& pose, double at_s,
                                                          bool keep_velocity) {
  if (!moving_caster_) return base::Unexpected<std::string>("move-object: this world is not editable ('" + std::string(name) + "')");
  return moving_caster_->move_object(name, pose, at_s, keep_velocity);
}

base::Expected<double, std::string> SceneWorld::add_object(scene::SceneObject object, double at_s,
                                                         std::shared_ptr<const raycast::TriMeshData> mesh) {
  if (!moving_caster_) return base::Unexpected<std::string>("add-object: this world is not editable");
  return moving_caster_->add_object(std::move(object), at_s, std::move(mesh));
}

base::Expected<double, std::string> SceneWorld::remove_object(std::string_view name, double at_s) {
  if (!moving_caster_) return base::Unexpected<std::string>("remove-object: this world is not editable ('" + std::string(name) + "')");
  return moving_caster_->remove_object(name, at_s);
}

ScenePlant::ScenePlant(const scene::Scene& scene, SceneWorld& world, std::optional<std::uint32_t> own_housing)
    : sensor_(scene, world.caster(), own_housing.value_or(raycast::kNoObject)),
      tilt_(std::make_unique<TiltPlate>(motor::make_tilt_motor(scene))),
      head_(scene.scanner.head) {
  board_.emplace(*tilt_);
  if (scene.effects.has(scene::Effect::head_dynamics)) {
    ripple_ = std::make_unique<motor::HeadRippleTrack>(scene.scanner.head);
  }
  measurement_ = std::make_unique<SceneMeasurement>(sensor_, *tilt_, scene.effects.has(scene::Effect::sweep_motion),
                                                    ripple_.get(), world.timing());
}

}  // namespace ldoem::plant
