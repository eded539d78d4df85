// D13 snr_noise, atmosphere and retro-reflectors through the whole pipeline: detection near the
// threshold is a coin the beam's own stream throws, range sigma grows as the signal falls, fog
// attenuates both ways, and a retro-reflector is seen far beyond a white wall's reach.
#include "fake_casters.hpp"

#include <ldoem/scene/optics.hpp>
#include <ldoem/sensor/sensor_model.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace ldoem::sensor {
namespace {

using scene::Effect;
using testing::PlaneCaster;
using testing::wall_at;

// A scene whose range limit is 250 m, far beyond a white wall's reach at the threshold (63.1 m).
scene::Scene long_range_scene(std::initializer_list<Effect> effects) {
  scene::Scene scene;
  scene.scanner.max_range_m = 250.0;
  for (Effect effect : effects) scene.effects.add(effect);
  return scene;
}

// `count` beams straight ahead, each its own noise stream (beam index i).
std::vector<BeamSample> measure_straight(const scene::Scene& scene, const raycast::RayCaster& caster, int count,
                                         MeasureStats* stats = nullptr) {
  const SensorModel model(scene, caster);
  std::vector<BeamRequest> beams;
  for (int i = 0; i < count; ++i) beams.push_back({.head_angle_rad = 0.0, .tilt_rad = 0.0, .beam_index = static_cast<std::uint32_t>(i)});
  std::vector<BeamSample> samples(beams.size());
  const MeasureStats counted = model.measure_counted(0, beams, samples);
  if (stats) *stats = counted;
  return samples;
}

struct RangeStatistics {
  double detected_share;
  double mean_m;
  double sigma_m;
};

RangeStatistics statistics(const std::vector<BeamSample>& samples) {
  double sum = 0.0;
  double sum_squares = 0.0;
  int detected = 0;
  for (const BeamSample& sample : samples) {
    if (sample.distance == 0) continue;
    const double range_m = sample.distance / kDistanceUnitsPerMetre;
    sum += range_m;
    sum_squares += range_m * range_m;
    ++detected;
  }
  const double mean = detected ? sum / detected : 0.0;
  const double variance = detected > 1 ? (sum_squares - detected * mean * mean) / (detected - 1) : 0.0;
  return {static_cast<double>(detected) / static_cast<double>(samples.size()), mean, std::sqrt(std::max(variance, 0.0))};
}

TEST(SnrNoise, AtTheThreshold_DetectedAboutHalfTheTime) {
  // A white wall at exactly l_max = 63.1 m returns I_rs_min: a fair coin for every beam.
  const auto stats = statistics(measure_straight(long_range_scene({Effect::snr_noise}), wall_at(63.1), 4000));
  EXPECT_NEAR(stats.detected_share, 0.5, 0.04);
}

// The stage alone on a white wall at `distance_m`, `count` beams: the unquantised ranges
// (1/256 m steps would blur a 1.5 mm sigma).
RangeStatistics stage_statistics(double distance_m, int count) {
  const auto stage = make_snr_noise_stage(long_range_scene({}).scanner, false);
  const PlaneCaster wall = wall_at(distance_m);
  double sum = 0.0;
  double sum_squares = 0.0;
  int detected = 0;
  for (int i = 0; i < count; ++i) {
    BeamState beam;
    beam.has_return = true;
    beam.range_m = distance_m;
    beam.reflectance = 1.0;
    BeamCounters counters;
    stage->apply(beam, BeamContext{.caster = wall, .seed = 7, .revolution = 0, .beam_index = static_cast<std::uint32_t>(i)},
                 counters);
    if (!beam.has_return) continue;
    sum += beam.range_m;
    sum_squares += beam.range_m * beam.range_m;
    ++detected;
  }
  const double mean = sum / detected;
  return {static_cast<double>(detected) / count, mean, std::sqrt((sum_squares - detected * mean * mean) / (detected - 1))};
}

// The pulse's sigma in range: 4 ns FWHM / 2.3548 * c / 2.
const double kPulseSigma_m = 4e-9 / (2.0 * std::sqrt(2.0 * std::numbers::ln2)) * 299792458.0 / 2.0;

TEST(SnrNoise, StrongReturn_AlwaysDetectedAndSigmaIsTheFloor) {
  // 5 m: SNR = 5 (63.1 / 5)^2 = 796, jitter 0.25 m / 796 = 0.32 mm under the 1.5 mm floor.
  const auto stats = stage_statistics(5.0, 20000);
  EXPECT_EQ(stats.detected_share, 1.0);
  EXPECT_NEAR(stats.mean_m, 5.0, 0.0001);
  const double expected = std::hypot(0.0015, kPulseSigma_m / (5.0 * std::pow(63.1 / 5.0, 2)));
  EXPECT_NEAR(stats.sigma_m, expected, 0.03 * expected);
}

TEST(SnrNoise, WeakReturn_SigmaGrowsAsTheSnrFalls) {
  // 40 m: SNR = 5 (63.1 / 40)^2 = 12.4, jitter 20.5 mm.
  const auto stats = stage_statistics(40.0, 20000);
  EXPECT_GT(stats.detected_share, 0.99);
  const double expected = std::hypot(0.0015, kPulseSigma_m / (5.0 * std::pow(63.1 / 40.0, 2)));
  EXPECT_NEAR(stats.sigma_m, expected, 0.03 * expected);
}

TEST(SnrNoise, SameSeed_SameSamples_MissesDrawNothing) {
  const scene::Scene scene = long_range_scene({Effect::snr_noise, Effect::intensity});
  EXPECT_EQ(measure_straight(scene, wall_at(60.0), 200), measure_straight(scene, wall_at(60.0), 200));
  MeasureStats stats;
  (void)measure_straight(scene, testing::MissCaster(), 10, &stats);
  EXPECT_EQ(stats.random_draws, 0u);
}

TEST(Atmosphere, TwoWayBeerLambert_OnTheEcho) {
  scene::Scene clear = long_range_scene({Effect::intensity});
  clear.scanner.optics.echo_scale = scene::EchoScale::log;
  scene::Scene foggy = clear;
  foggy.effects.add(Effect::atmosphere);
  foggy.scanner.atmosphere.visibility_m = 100.0;
  const BeamSample in_clear = measure_straight(clear, wall_at(20.0), 1)[0];
  const BeamSample in_fog = measure_straight(foggy, wall_at(20.0), 1)[0];
  ASSERT_NE(in_clear.distance, 0);
  ASSERT_NE(in_fog.distance, 0);
  EXPECT_EQ(in_clear.distance, in_fog.distance);
  // log ECHO: the transmission exp(-2 * 3.912 / 100 * 20) shows as 8000 log10 of it.
  const double expected_drop = -8000.0 * std::log10(std::exp(-2.0 * 3.912 / 100.0 * 20.0));
  EXPECT_NEAR(in_clear.echo - in_fog.echo, expected_drop, 1.0);
  // The reach shrinks: 50 m is seen in clear air, not in this fog.
  EXPECT_NE(measure_straight(clear, wall_at(50.0), 1)[0].distance, 0);
  EXPECT_EQ(measure_straight(foggy, wall_at(50.0), 1)[0].distance, 0);
}

TEST(RetroReflective, SeenFarBeyondAWhiteWallsReach) {
  const scene::Scene scene = long_range_scene({Effect::intensity});
  EXPECT_EQ(measure_straight(scene, wall_at(200.0, 1.0), 1)[0].distance, 0);
  EXPECT_NE(measure_straight(scene, wall_at(200.0, scene::kRetroReflectiveGain), 1)[0].distance, 0);
}

TEST(EchoScale, LogScale_CorridorDistancesDoNotSaturate) {
  scene::Scene scene = long_range_scene({Effect::intensity});
  scene.scanner.optics.echo_scale = scene::EchoScale::log;
  std::uint16_t previous = 65535;
  for (double distance_m : {0.95, 2.8, 4.18, 10.0, 30.0}) {
    const BeamSample sample = measure_straight(scene, wall_at(distance_m), 1)[0];
    EXPECT_LT(sample.echo, 65535) << distance_m;
    EXPECT_LT(sample.echo, previous) << distance_m;  // farther, weaker, lower
    previous = sample.echo;
  }
}

}  // namespace
}  // namespace ldoem::sensor
