// Issue 26, downstream: the sensor model's own arithmetic (D5 beam geometry, mixed pixels,
// waveform peak detection) on the hard scenes with noise off. Every ray the model casts is
// recorded and answered by the exact oracle; each sample's range must lie within one
// quantisation step (1/256 m) of the exact range of its beam's rays (of the nearest and farthest
// of them when mixed pixels split a beam into several), and no sample may be NaN (a distance
// beyond the scanner's range cannot be encoded, so it shows as one).
#include "differential.hpp"

#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/scene/scene_loader.hpp"
#include "ldoem/sensor/sensor_model.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <mutex>
#include <numbers>

namespace ldoem::oracle {
namespace {

// Passes every ray on to the real caster and remembers it.
class Recorder final : public raycast::RayCaster {
 public:
  explicit Recorder(const raycast::RayCaster& inner) : inner_(inner) {}
  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override {
    const std::lock_guard lock(mutex_);
    rays.push_back(ray);
    return inner_.cast(ray);
  }
  mutable std::vector<raycast::Ray> rays;

 private:
  const raycast::RayCaster& inner_;
  mutable std::mutex mutex_;
};

void check_scene(const std::filesystem::path& file, std::initializer_list<scene::Effect> effects) {
  auto loaded = scene::load_scene(file);
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message();
  scene::Scene scene = std::move(loaded).value();
  scene.effects = scene::EffectSet{};
  for (const scene::Effect effect : effects) scene.effects.add(effect);
  const raycast::OdeWorld world(scene);
  const raycast::EmbreeRayCaster caster(world);
  const Recorder recorder(caster);
  const sensor::SensorModel model(scene, recorder);
  const std::vector<Part> parts = parts_of(world);
  constexpr double kStep = 1.0 / sensor::kDistanceUnitsPerMetre;
  std::size_t compared = 0;
  for (int tilt_deg = -30; tilt_deg <= 30; tilt_deg += 10) {
    for (int i = 0; i < 180; ++i) {
      const sensor::BeamRequest beam{.head_angle_rad = (-180.0 + 2.0 * i) * std::numbers::pi / 180.0,
                                     .tilt_rad = tilt_deg * std::numbers::pi / 180.0,
                                     .beam_index = static_cast<std::uint32_t>(i)};
      recorder.rays.clear();
      sensor::BeamSample sample;
      model.measure(0, {&beam, 1}, {&sample, 1});
      if (sample.distance == 0) continue;
      double nearest = INFINITY, farthest = -INFINITY;
      for (const raycast::Ray& ray : recorder.rays) {
        const Answer exact = cast(parts, OracleRay{{ray.origin_m.x(), ray.origin_m.y(), ray.origin_m.z()},
                                             {ray.direction.x(), ray.direction.y(), ray.direction.z()}, ray.max_range_m},
                                  ray.ignored_object);
        if (!exact.hit) continue;
        nearest = std::min(nearest, exact.range_m);
        farthest = std::max(farthest, exact.range_m);
      }
      const double range_m = sample.distance * kStep;
      ASSERT_TRUE(std::isfinite(nearest)) << file << ": a return where every ray of the beam misses, tilt " << tilt_deg << " beam " << i;
      EXPECT_GE(range_m, nearest - kStep) << file << " tilt " << tilt_deg << " beam " << i;
      EXPECT_LE(range_m, farthest + kStep) << file << " tilt " << tilt_deg << " beam " << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 0u) << file;
}

TEST(SensorDownstream, HardScenesNoiseOff_RangeWithinOneStepOfExact) {
  using scene::Effect;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(LDOEM_SOURCE_DIR) / "scenes/hard")) {
    SCOPED_TRACE(entry.path().filename().string());
    check_scene(entry.path(), {});
    check_scene(entry.path(), {Effect::waveform});
    check_scene(entry.path(), {Effect::mixed_pixels});
    check_scene(entry.path(), {Effect::mixed_pixels, Effect::waveform, Effect::intensity, Effect::incidence});
  }
}

}  // namespace
}  // namespace ldoem::oracle
