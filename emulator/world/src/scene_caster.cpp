#include "ldoem/world/scene_caster.hpp"

#include <algorithm>

namespace ldoem::world {

SceneCaster::SceneCaster(const scene::Scene& scene, raycast::MovingCasterOptions options)
    : min_window_s_(options.min_window_s),
      motion_(scene), moving_caster_(motion_.moving_objects(), motion_.scene_indices(), motion_, options) {
  scene::Scene fixed;
  fixed.scanner = scene.scanner;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].moves()) continue;
    fixed.objects.push_back(scene.objects[i]);
    static_indices_.push_back(static_cast<std::uint32_t>(i));
  }
  if (!fixed.objects.empty()) {
    static_world_ = std::make_unique<raycast::OdeWorld>(fixed);
    static_caster_ = std::make_unique<raycast::EmbreeRayCaster>(*static_world_);
  }
}

SceneCaster::~SceneCaster() = default;

void SceneCaster::prepare(double t0_s, double t1_s) {
  if (motion_.moves_accepted() != moves_seen_) {  // a runtime move: the old boxes may not hold it
    moves_seen_ = motion_.moves_accepted();
    moving_caster_.invalidate();
  }
  motion_.advance(t0_s, std::max(t1_s, t0_s + min_window_s_));
  moving_caster_.prepare(t0_s, t1_s);
}

std::optional<raycast::Hit> SceneCaster::cast(const raycast::Ray& ray) const {
  std::optional<raycast::Hit> fixed;
  if (static_caster_) {
    fixed = static_caster_->cast(ray);
    if (fixed) fixed->object_index = static_indices_[fixed->object_index];
  }
  // The moving objects need only be searched up to the static hit; at an equal range the static
  // object wins (any fixed rule keeps the answer deterministic).
  raycast::Ray shorter = ray;
  if (fixed) shorter.max_range_m = fixed->range_m;
  auto moving = moving_caster_.cast(shorter);
  if (moving && (!fixed || moving->range_m < fixed->range_m)) return moving;
  return fixed;
}

}  // namespace ldoem::world
