// Helpers for the D12 tests: scenes from YAML text, rays at an instant, a caster that remembers
// the exact ranges it answered (before the sensor quantises them), the scenes' gravity.
#pragma once

#include "ldoem/scene/scene_loader.hpp"
#include "ldoem/world/scene_caster.hpp"

#include <gtest/gtest.h>

#include <mutex>
#include <string>
#include <vector>

namespace ldoem::world::testing {

// The magnitude of scene::WorldConfig's default gravity (m/s^2), which the falling bodies feel.
inline constexpr double kG = 9.81;

inline scene::Scene scene_from(const std::string& yaml) {
  auto scene = scene::load_scene_from_string(yaml, "test.yaml");
  if (!scene) {
    ADD_FAILURE() << scene.error().message();
    return {};
  }
  return *scene;
}

inline raycast::Ray ray_at(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double time_s,
                           double max_range_m = 100.0) {
  return raycast::Ray{origin, direction.normalized(), max_range_m, time_s};
}

class RecordingCaster final : public raycast::RayCaster {
 public:
  explicit RecordingCaster(const raycast::RayCaster& inner) : inner_(inner) {}
  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override {
    auto hit = inner_.cast(ray);
    const std::lock_guard lock(mutex_);
    ranges_.push_back(hit ? hit->range_m : -1.0);
    return hit;
  }
  std::vector<double> ranges() const {
    const std::lock_guard lock(mutex_);
    return ranges_;
  }

 private:
  const raycast::RayCaster& inner_;
  mutable std::mutex mutex_;
  mutable std::vector<double> ranges_;
};

inline const raycast::MovingCasterOptions kIndexOptions[] = {
    {raycast::MovingIndex::swept_slices, 1},
    {raycast::MovingIndex::swept_slices, 16},
    {raycast::MovingIndex::swept_slices, 4, 0.3, true},  // refitted rather than built per window
    {raycast::MovingIndex::motion_blur, 4},
};

}  // namespace ldoem::world::testing
