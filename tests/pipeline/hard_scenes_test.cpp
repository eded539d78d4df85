// Every committed scene, the hard ones above all, through the sensor pipeline with every sensor
// effect on (the two noise models in turn, as the loader refuses both at once): no crash, and
// every sample is either "no echo" (0, 0) or a range inside the scene's limits with an ECHO.
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/ode_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/scene/scene_loader.hpp"
#include "ldoem/sensor/sensor_model.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>

#include "committed_scenes.hpp"

namespace ldoem::sensor {
namespace {

using scene::Effect;

using test::kSceneFiles;
using test::kScenes;

const std::vector<std::vector<Effect>> kAllSensorEffects{
    {Effect::waveform, Effect::snr_noise, Effect::intensity, Effect::incidence, Effect::atmosphere,
     Effect::mixed_pixels},
    {Effect::waveform, Effect::noise, Effect::intensity, Effect::incidence, Effect::atmosphere},
    {Effect::mixed_pixels, Effect::noise, Effect::intensity, Effect::incidence, Effect::atmosphere},
};

template <class Caster>
void check_scene(const std::string& file, const std::vector<Effect>& effects) {
  auto loaded = scene::load_scene(kScenes / file);
  ASSERT_TRUE(loaded.has_value()) << loaded.error().message();
  scene::Scene scene = std::move(loaded).value();
  scene.effects = scene::EffectSet{};
  for (Effect effect : effects) scene.effects.add(effect);
  scene.scanner.atmosphere.visibility_m = 300.0;
  scene.scanner.optics.echo_scale = scene::EchoScale::log;
  const raycast::OdeWorld world(scene);
  const Caster caster(world);
  const SensorModel model(scene, caster);
  const double min_q8 = scene.scanner.min_range_m * kDistanceUnitsPerMetre;
  const double max_q8 = scene.scanner.max_range_m * kDistanceUnitsPerMetre;
  std::size_t returns = 0;
  for (int tilt_deg = -30; tilt_deg <= 30; tilt_deg += 5) {
    std::vector<BeamRequest> beams;
    for (int i = 0; i < 720; ++i) {
      beams.push_back(BeamRequest{.head_angle_rad = (-180.0 + 0.5 * i) * std::numbers::pi / 180.0,
                                  .tilt_rad = tilt_deg * std::numbers::pi / 180.0,
                                  .beam_index = static_cast<std::uint32_t>(i)});
    }
    std::vector<BeamSample> samples(beams.size());
    model.measure(static_cast<std::uint32_t>(tilt_deg + 30), beams, samples);
    for (const BeamSample& sample : samples) {
      if (sample.distance == 0) {
        EXPECT_EQ(sample.echo, 0) << file;
        continue;
      }
      ++returns;
      EXPECT_GE(sample.distance, std::floor(min_q8)) << file;
      EXPECT_LE(sample.distance, std::ceil(max_q8)) << file;
      EXPECT_GT(sample.echo, 0) << file;
    }
  }
  EXPECT_GT(returns, 0u) << file << ": the scene should show something";
}

TEST(HardScenes, EveryEffectOn_SamplesAreNoEchoOrInsideTheLimits_Embree) {
  for (const std::string& file : kSceneFiles) {
    for (const auto& effects : kAllSensorEffects) check_scene<raycast::EmbreeRayCaster>(file, effects);
  }
}

TEST(HardScenes, EveryEffectOn_SamplesAreNoEchoOrInsideTheLimits_Ode) {
  for (const std::string& file : kSceneFiles) check_scene<raycast::OdeRayCaster>(file, kAllSensorEffects.front());
}

}  // namespace
}  // namespace ldoem::sensor
