// D12: the caster of a scene in which something moves. Static objects go to EmbreeRayCaster
// (exactly as in a static scene), moving ones to MovingRayCaster; a ray is answered by the
// nearer of the two at the ray's instant (Ray::time_s). The daemon builds this only when
// Scene::moves() is true; otherwise it builds EmbreeRayCaster alone, as before D12.
#pragma once

#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/moving_ray_caster.hpp"
#include "ldoem/world/world_motion.hpp"

#include <memory>

namespace ldoem::world {

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

 private:
  double min_window_s_;
  std::uint64_t moves_seen_ = 0;
  WorldMotion motion_;
  std::vector<std::uint32_t> static_indices_;  // static caster's object index -> Scene::objects
  std::unique_ptr<raycast::OdeWorld> static_world_;
  std::unique_ptr<raycast::EmbreeRayCaster> static_caster_;
  raycast::MovingRayCaster moving_caster_;
};

}  // namespace ldoem::world
