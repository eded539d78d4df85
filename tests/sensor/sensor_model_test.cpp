#include "fake_casters.hpp"
#include "degrees.hpp"

#include <ldoem/scene/optics.hpp>
#include <ldoem/sensor/beam_geometry.hpp>
#include <ldoem/sensor/sensor_model.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <thread>
#include <vector>

namespace ldoem::sensor {
namespace {

using scene::Effect;
using testing::BrokenRangeCaster;
using testing::DepthStepCaster;
using testing::MissCaster;
using testing::PlaneCaster;
using testing::kDeg;
using testing::wall_at;

scene::Scene make_scene(std::initializer_list<Effect> effects) {
  scene::Scene scene;
  scene.scanner.optics.calibration = scene::calibration_for_max_range(scene.scanner.optics, 63.1);
  for (Effect effect : effects) scene.effects.add(effect);
  return scene;
}

BeamSample measure_one(const scene::Scene& scene, const raycast::RayCaster& caster, double head_rad = 0.0,
                       double tilt_rad = 0.0, std::uint32_t revolution = 0, std::uint32_t beam_index = 0) {
  const SensorModel model(scene, caster);
  const BeamRequest request{.head_angle_rad = head_rad, .tilt_rad = tilt_rad, .beam_index = beam_index};
  BeamSample sample;
  model.measure(revolution, std::span(&request, 1), std::span(&sample, 1));
  return sample;
}

std::vector<BeamRequest> fan_of_beams(std::size_t count) {
  std::vector<BeamRequest> beams;
  for (std::size_t i = 0; i < count; ++i) {
    // +-30 deg around +x, so every beam meets a wall at x = const.
    beams.push_back({.head_angle_rad = (-30.0 + 60.0 * static_cast<double>(i) / static_cast<double>(count)) * kDeg,
                     .tilt_rad = 0.0,
                     .beam_index = static_cast<std::uint32_t>(i)});
  }
  return beams;
}

TEST(EffectPipeline, NoEffects_OnlySingleRayStage) {
  const auto pipeline = EffectPipeline::build(scene::ScannerConfig{}, scene::EffectSet{});
  EXPECT_EQ(pipeline.stage_names(), (std::vector<std::string_view>{"single_ray"}));
}

// The no-effect pipeline skips the stage machinery; its answers must be those of the single-ray
// stage followed by the encoder, for hits, misses, out-of-limit and broken ranges alike.
TEST(EffectPipeline, NoEffectsFastPath_EqualsSingleRayStageAndEncoder) {
  const scene::ScannerConfig scanner;
  const auto pipeline = EffectPipeline::build(scanner, scene::EffectSet{});
  const auto single_ray = make_single_ray_stage();
  const PlaneCaster near_wall = wall_at(0.5);
  const PlaneCaster wall = wall_at(7.3);
  const PlaneCaster far_wall = wall_at(80.0);
  const MissCaster miss;
  const BrokenRangeCaster broken(std::nan(""));
  const raycast::RayCaster* casters[] = {&near_wall, &wall, &far_wall, &miss, &broken};
  for (const raycast::RayCaster* caster : casters) {
    for (const BeamRequest& request : fan_of_beams(25)) {
      const raycast::Ray ray = beam_ray(scanner, request.head_angle_rad, 0.0, pipeline.cast_range_m());
      const BeamContext context{.caster = *caster, .seed = 1, .revolution = 0, .beam_index = request.beam_index};
      BeamCounters fast_counters;
      BeamCounters staged_counters;
      BeamState staged;
      staged.ray = ray;
      single_ray->apply(staged, context, staged_counters);
      const BeamSample expected = encode_beam(staged, pipeline.limits());
      const BeamSample fast = pipeline.run(ray, context, fast_counters);
      EXPECT_EQ(fast.distance, expected.distance);
      EXPECT_EQ(fast.echo, expected.echo);
      EXPECT_EQ(fast_counters.rays_cast, staged_counters.rays_cast);
    }
  }
}

TEST(EffectPipeline, OrderIsFixed_NotTheOrderEffectsWereNamed) {
  scene::EffectSet forwards;
  for (Effect effect : {Effect::mixed_pixels, Effect::intensity, Effect::noise}) forwards.add(effect);
  scene::EffectSet backwards;
  for (Effect effect : {Effect::noise, Effect::intensity, Effect::mixed_pixels}) backwards.add(effect);
  const std::vector<std::string_view> expected{"mixed_pixels", "intensity", "noise"};
  EXPECT_EQ(EffectPipeline::build(scene::ScannerConfig{}, forwards).stage_names(), expected);
  EXPECT_EQ(EffectPipeline::build(scene::ScannerConfig{}, backwards).stage_names(), expected);
}

TEST(EffectPipeline, NonSensorEffects_BuildNoStage) {
  scene::EffectSet effects;
  for (Effect effect : {Effect::motor_dynamics, Effect::head_dynamics, Effect::sweep_motion, Effect::bus_timing})
    effects.add(effect);
  EXPECT_EQ(EffectPipeline::build(scene::ScannerConfig{}, effects).stage_names(),
            (std::vector<std::string_view>{"single_ray"}));
}

TEST(SensorModel, PlainWall_ExactQuantisedDistanceAndConstantEcho) {
  const PlaneCaster wall = wall_at(5.0);
  EXPECT_EQ(measure_one(make_scene({}), wall), (BeamSample{.distance = 1280, .echo = kEchoWithoutIntensity}));
}

TEST(SensorModel, AngledBeam_RangeAlongTheBeam) {
  const PlaneCaster wall = wall_at(5.0);
  const BeamSample sample = measure_one(make_scene({}), wall, 60 * kDeg);  // 5 / cos 60 = 10 m
  EXPECT_EQ(sample.distance, 2560);
}

TEST(SensorModel, Miss_NoEcho) {
  const MissCaster nothing;
  EXPECT_EQ(measure_one(make_scene({Effect::intensity, Effect::noise}), nothing), BeamSample{});
}

TEST(SensorModel, BelowMinimumRange_NoEcho) {
  const PlaneCaster wall = wall_at(0.5);
  EXPECT_EQ(measure_one(make_scene({}), wall), BeamSample{});
}

TEST(SensorModel, AboveMaximumRangeButInsideCastMargin_NoEcho) {
  const PlaneCaster wall = wall_at(30.5);
  EXPECT_EQ(measure_one(make_scene({}), wall), BeamSample{});
}

TEST(SensorModel, BeyondCastRange_NoEcho) {
  const PlaneCaster wall = wall_at(100.0);
  EXPECT_EQ(measure_one(make_scene({}), wall), BeamSample{});
}

TEST(SensorModel, CasterReturnsNaNOrInfiniteRange_NoEcho) {
  for (double broken : {std::nan(""), std::numeric_limits<double>::infinity(), 0.0, -3.0}) {
    SCOPED_TRACE(broken);
    const BrokenRangeCaster caster(broken);
    EXPECT_EQ(measure_one(make_scene({}), caster), BeamSample{});
    EXPECT_EQ(measure_one(make_scene({Effect::intensity, Effect::incidence, Effect::noise}), caster), BeamSample{});
    EXPECT_EQ(measure_one(make_scene({Effect::mixed_pixels, Effect::intensity, Effect::noise}), caster),
              BeamSample{});
  }
}

TEST(SensorModel, Intensity_EchoFollowsInverseSquare) {
  const PlaneCaster wall = wall_at(10.0);
  // I_rs / I_min = (63.1 / 10)^2 at r = 1, head-on.
  const auto expected = static_cast<std::uint16_t>(std::lround(1000.0 * 63.1 * 63.1 / 100.0));
  EXPECT_EQ(measure_one(make_scene({Effect::intensity}), wall), (BeamSample{.distance = 2560, .echo = expected}));
}

TEST(SensorModel, Intensity_DarkFarTargetDropsOut) {
  const PlaneCaster dark_wall = wall_at(25.0, 0.1);  // l_max = 63.1 sqrt(0.1) = 19.95 m
  EXPECT_EQ(measure_one(make_scene({Effect::intensity}), dark_wall), BeamSample{});
  EXPECT_EQ(measure_one(make_scene({}), dark_wall).distance, 6400);  // without intensity it returns
}

TEST(SensorModel, Intensity_NearTargetSaturatesEcho) {
  const PlaneCaster wall = wall_at(1.0);
  EXPECT_EQ(measure_one(make_scene({Effect::intensity}), wall).echo, 65535);
}

TEST(SensorModel, Incidence_HalvesEchoAtSixtyDegrees) {
  // Wall whose normal is 60 deg from the beam: n = (cos 60, sin 60, 0) . p = 10 * cos 60.
  const PlaneCaster slanted(Eigen::Vector3d(std::cos(60 * kDeg), std::sin(60 * kDeg), 0), 5.0, 1.0);
  const BeamSample head_on_model = measure_one(make_scene({Effect::intensity}), slanted);
  const BeamSample lambert = measure_one(make_scene({Effect::intensity, Effect::incidence}), slanted);
  ASSERT_EQ(head_on_model.distance, lambert.distance);
  EXPECT_NEAR(static_cast<double>(lambert.echo) / head_on_model.echo, 0.5, 1e-3);
}

TEST(SensorModel, Incidence_GrazingWallDropsOut) {
  // Normal at 89.9 deg from the beam: cos alpha = 0.0017, l_max = 63.1 * 0.042 = 2.6 m < 5 m.
  const double angle = 89.9 * kDeg;
  const PlaneCaster grazing(Eigen::Vector3d(std::cos(angle), std::sin(angle), 0), 5.0 * std::cos(angle), 1.0);
  EXPECT_EQ(measure_one(make_scene({Effect::intensity, Effect::incidence}), grazing), BeamSample{});
}

TEST(SensorModel, MixedPixelsAtDepthStep_RangeFallsBetweenTheSurfaces) {
  const DepthStepCaster step(5.0, 10.0, 1.0);
  const BeamSample at_edge = measure_one(make_scene({Effect::mixed_pixels}), step);
  const double range_m = at_edge.distance / 256.0;
  EXPECT_GT(range_m, 5.0 + 1.0 / 256);
  EXPECT_LT(range_m, 10.0 - 1.0 / 256);
  // 7 sub-rays: centre and 3 ring points on the near side (y >= 0), 3 on the far side; weights
  // are irradiances, 4x larger at half the range: (4*4*5 + 3*10) / (4*4 + 3).
  EXPECT_NEAR(range_m, (16.0 * 5.0 + 3.0 * 10.0) / 19.0, 1.0 / 256);
}

TEST(SensorModel, MixedPixelsAwayFromEdge_SameAsSingleRay) {
  const DepthStepCaster step(5.0, 10.0, 1.0);
  const BeamSample clear = measure_one(make_scene({Effect::mixed_pixels}), step, 5 * kDeg);
  EXPECT_EQ(clear.distance, measure_one(make_scene({}), step, 5 * kDeg).distance);
}

TEST(SensorModel, MixedPixelsWithIntensity_EchoDropsAtEdge) {
  const DepthStepCaster step(20.0, 28.0, 1.0);  // far enough that echoes do not saturate
  const scene::Scene scene = make_scene({Effect::mixed_pixels, Effect::intensity});
  EXPECT_LT(measure_one(scene, step).echo, measure_one(scene, step, 5 * kDeg).echo);
}

TEST(SensorModel, HexagonalPattern_CountsAndExtent) {
  for (int count : {1, 7, 19, 37}) {
    const auto offsets = hexagonal_subray_offsets(0.004, count);
    EXPECT_EQ(static_cast<int>(offsets.size()), count);
    double widest = 0.0;
    for (const auto& offset : offsets) widest = std::max(widest, offset.norm());
    EXPECT_NEAR(widest, count == 1 ? 0.0 : 0.002, 1e-15);  // outer corners on the half angle
  }
  EXPECT_EQ(hexagonal_subray_offsets(0.004, 20).size(), 19u);  // rounded down to a full ring
}

TEST(SensorModel, MixedPixels_CastsOneRayPerSubray) {
  const PlaneCaster wall = wall_at(5.0);
  scene::Scene scene = make_scene({Effect::mixed_pixels});
  scene.scanner.mixed_pixel_subrays = 19;
  const SensorModel model(scene, wall);
  const auto beams = fan_of_beams(10);
  std::vector<BeamSample> out(beams.size());
  EXPECT_EQ(model.measure_counted(0, beams, out).rays_cast, 190u);
}

TEST(SensorModel, SceneWithoutNoise_DrawsNoRandomNumbers) {
  const PlaneCaster wall = wall_at(5.0);
  const SensorModel model(make_scene({Effect::mixed_pixels, Effect::intensity, Effect::incidence}), wall);
  const auto beams = fan_of_beams(100);
  std::vector<BeamSample> out(beams.size());
  const MeasureStats stats = model.measure_counted(0, beams, out);
  EXPECT_EQ(stats.random_draws, 0u);
  EXPECT_EQ(stats.rays_cast, 700u);
}

TEST(SensorModel, Noise_DrawsOnlyForReturns) {
  const PlaneCaster wall = wall_at(5.0);
  const SensorModel model(make_scene({Effect::noise}), wall);
  std::vector<BeamRequest> beams = fan_of_beams(10);
  beams[3].head_angle_rad = std::numbers::pi;  // looks away from the wall: a miss
  std::vector<BeamSample> out(beams.size());
  EXPECT_EQ(model.measure_counted(0, beams, out).random_draws, 9u * 2u);
  EXPECT_EQ(out[3], BeamSample{});
}

TEST(SensorModel, SameInputs_IdenticalSamples) {
  const PlaneCaster wall = wall_at(7.0, 0.6);
  const scene::Scene scene = make_scene({Effect::mixed_pixels, Effect::intensity, Effect::incidence, Effect::noise});
  const SensorModel model(scene, wall);
  const auto beams = fan_of_beams(361);
  std::vector<BeamSample> first(beams.size());
  std::vector<BeamSample> second(beams.size());
  model.measure(12, beams, first);
  SensorModel(scene, wall).measure(12, beams, second);
  EXPECT_EQ(first, second);
}

TEST(SensorModel, OrderOfBeams_DoesNotChangeTheirSamples) {
  const PlaneCaster wall = wall_at(7.0);
  const SensorModel model(make_scene({Effect::noise}), wall);
  auto beams = fan_of_beams(50);
  std::vector<BeamSample> forwards(beams.size());
  model.measure(3, beams, forwards);
  std::reverse(beams.begin(), beams.end());
  std::vector<BeamSample> backwards(beams.size());
  model.measure(3, beams, backwards);
  std::reverse(backwards.begin(), backwards.end());
  EXPECT_EQ(forwards, backwards);
}

TEST(SensorModel, ConcurrentCallers_SameSamplesAsOne) {
  const PlaneCaster wall = wall_at(7.0);
  const SensorModel model(make_scene({Effect::intensity, Effect::noise}), wall);
  const auto beams = fan_of_beams(2000);
  std::vector<BeamSample> alone(beams.size());
  model.measure(5, beams, alone);
  std::vector<BeamSample> left(beams.size());
  std::vector<BeamSample> right(beams.size());
  std::thread other([&] { model.measure(5, beams, left); });
  model.measure(5, beams, right);
  other.join();
  EXPECT_EQ(left, alone);
  EXPECT_EQ(right, alone);
}

TEST(SensorModel, DifferentSeedOrRevolution_DifferentNoise) {
  const PlaneCaster wall = wall_at(7.0);
  scene::Scene scene = make_scene({Effect::noise});
  const auto beams = fan_of_beams(100);
  std::vector<BeamSample> seed_one(beams.size());
  std::vector<BeamSample> seed_two(beams.size());
  std::vector<BeamSample> next_revolution(beams.size());
  SensorModel(scene, wall).measure(0, beams, seed_one);
  SensorModel(scene, wall).measure(1, beams, next_revolution);
  scene.seed = 2;
  SensorModel(scene, wall).measure(0, beams, seed_two);
  EXPECT_NE(seed_one, seed_two);
  EXPECT_NE(seed_one, next_revolution);
}

// 1e5 beams on a wall at 10 m, sigma 10 mm, mean offset 2 mm: the quantised distances have mean
// 10.002 m within 0.2 mm (~6 standard errors of 0.032 mm) and sigma within 3 % of
// sqrt(sigma^2 + q^2/12) (quantisation q = 1/256 m adds its own variance). Fixed seed.
TEST(SensorModel, NoiseStatistics_MatchSigmaAndMean) {
  const PlaneCaster wall = wall_at(10.0);
  scene::Scene scene = make_scene({Effect::noise});
  scene.scanner.noise = {.sigma_m = 0.010, .mean_m = 0.002};
  scene.seed = 77;
  const SensorModel model(scene, wall);
  std::vector<BeamRequest> beams(1000, BeamRequest{});
  for (std::uint32_t i = 0; i < beams.size(); ++i) beams[i].beam_index = i;
  std::vector<BeamSample> out(beams.size());
  double sum = 0.0;
  double sum_sq = 0.0;
  for (std::uint32_t revolution = 0; revolution < 100; ++revolution) {
    model.measure(revolution, beams, out);
    for (const BeamSample& sample : out) {
      const double range_m = sample.distance / 256.0;
      sum += range_m;
      sum_sq += range_m * range_m;
    }
  }
  const double count = 1e5;
  const double mean = sum / count;
  const double sigma = std::sqrt(sum_sq / count - mean * mean);
  EXPECT_NEAR(mean, 10.002, 2e-4);
  const double expected_sigma = std::sqrt(0.010 * 0.010 + std::pow(1.0 / 256, 2) / 12.0);
  EXPECT_NEAR(sigma, expected_sigma, 0.03 * expected_sigma);
}

TEST(SensorModel, ShortOutputSpan_MeasuresWhatFits_LongOneClearsTheRest) {
  const PlaneCaster wall = wall_at(5.0);
  const SensorModel model(make_scene({}), wall);
  const auto beams = fan_of_beams(3);
  std::vector<BeamSample> out(5, BeamSample{.distance = 9, .echo = 9});
  model.measure(0, beams, out);
  EXPECT_NE(out[2].distance, 0);
  EXPECT_EQ(out[3], BeamSample{});
  EXPECT_EQ(out[4], BeamSample{});
}

TEST(SensorModel, TiltedBeamOverFloor_MeetsItWhereGeometrySays) {
  // Floor z = 0, pivot 1 m up, beam tilted down 30 deg: range = 1 / sin 30 = 2 m.
  const PlaneCaster floor(Eigen::Vector3d::UnitZ(), 0.0, 1.0);
  scene::Scene scene = make_scene({});
  scene.scanner.pivot_pose.position_m = {0, 0, 1};
  EXPECT_EQ(measure_one(scene, floor, 0.0, -30 * kDeg).distance, 512);
  EXPECT_EQ(measure_one(scene, floor, 0.0, 30 * kDeg), BeamSample{});  // looking up: nothing
}

}  // namespace
}  // namespace ldoem::sensor
