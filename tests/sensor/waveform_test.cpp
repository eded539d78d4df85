// D13 waveform: one echo out of the footprint's summed pulses. At a depth step the beam reports
// one surface or the other, never mid-air; a clean pulse is measured at its centre whatever its
// height; a slanted surface stretches the pulse and its range walks; the threshold is D6's.
#include "fake_casters.hpp"
#include "degrees.hpp"

#include <ldoem/scene/optics.hpp>
#include <ldoem/sensor/beam_geometry.hpp>
#include <ldoem/sensor/effects.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace ldoem::sensor {
namespace {

using testing::DepthStepCaster;
using testing::MissCaster;
using testing::PlaneCaster;

using testing::kDeg;

scene::ScannerConfig scanner_with(scene::EchoDetection detection = scene::EchoDetection::first) {
  scene::ScannerConfig scanner;
  scanner.max_range_m = 100.0;
  scanner.waveform.detection = detection;
  return scanner;
}

// The stage alone, its unquantised range (or nothing) for a beam along `direction`.
std::optional<BeamState> run_stage(const BeamStage& stage, const raycast::RayCaster& caster,
                                   Eigen::Vector3d direction = Eigen::Vector3d::UnitX()) {
  BeamState beam;
  beam.ray = raycast::Ray{.origin_m = Eigen::Vector3d::Zero(), .direction = direction.normalized(), .max_range_m = 101.0};
  BeamCounters counters;
  stage.apply(beam, BeamContext{.caster = caster}, counters);
  if (!beam.has_return) return std::nullopt;
  return beam;
}

TEST(Waveform, WallHeadOn_CentreOfThePulseAtAnyHeight) {
  const auto stage = make_waveform_stage(scanner_with(), false);
  for (double distance_m : {1.0, 4.18, 20.0, 60.0}) {
    const PlaneCaster wall(Eigen::Vector3d::UnitX(), distance_m, 1.0);
    const auto beam = run_stage(*stage, wall);
    ASSERT_TRUE(beam.has_value()) << distance_m;
    // Sub-rays off axis travel 1/cos(1.25 mrad) further: under a micrometre at 60 m.
    EXPECT_NEAR(beam->range_m, distance_m, 1e-4) << distance_m;
    // One clean pulse: its peak is the beam's whole I_rs.
    const double expected = scene::received_irradiance(scanner_with().optics, 1.0, 1.0, distance_m);
    // (the off-axis sub-rays' 1/cos^2 of 1.25 mrad is 1.6e-6 less power)
    EXPECT_NEAR(*beam->irradiance, expected, 1e-5 * expected) << distance_m;
  }
}

TEST(Waveform, BeyondTheThreshold_NoEcho) {
  const auto stage = make_waveform_stage(scanner_with(), false);
  // D6: r = 0.5 drops out at 63.1 m * sqrt(0.5) = 44.6 m.
  EXPECT_TRUE(run_stage(*stage, PlaneCaster(Eigen::Vector3d::UnitX(), 44.0, 0.5)).has_value());
  EXPECT_FALSE(run_stage(*stage, PlaneCaster(Eigen::Vector3d::UnitX(), 45.5, 0.5)).has_value());
  EXPECT_FALSE(run_stage(*stage, MissCaster()).has_value());
}

TEST(Waveform, HigherThresholdFactor_ShortensTheReach) {
  scene::ScannerConfig scanner = scanner_with();
  scanner.waveform.threshold_factor = 4.0;  // l_max halves
  const auto stage = make_waveform_stage(scanner, false);
  EXPECT_TRUE(run_stage(*stage, PlaneCaster(Eigen::Vector3d::UnitX(), 31.0, 1.0)).has_value());
  EXPECT_FALSE(run_stage(*stage, PlaneCaster(Eigen::Vector3d::UnitX(), 32.0, 1.0)).has_value());
}

// A beam centred on the edge of a depth step (2.8 m / 4.18 m, the corridor's cylinder and wall):
// half its sub-rays on each side.
TEST(Waveform, BeamOnADepthStep_OneSurfaceOrTheOtherNeverBetween) {
  const DepthStepCaster step(2.8, 4.18, 0.7);
  const auto first = run_stage(*make_waveform_stage(scanner_with(scene::EchoDetection::first), false), step);
  const auto last = run_stage(*make_waveform_stage(scanner_with(scene::EchoDetection::last), false), step);
  const auto strongest =
      run_stage(*make_waveform_stage(scanner_with(scene::EchoDetection::strongest), false), step);
  ASSERT_TRUE(first && last && strongest);
  EXPECT_NEAR(first->range_m, 2.8, 0.01);
  EXPECT_NEAR(last->range_m, 4.18, 0.01);
  // Both halves carry similar shares of sub-rays; the near one returns more power (1 / l^2).
  EXPECT_NEAR(strongest->range_m, 2.8, 0.01);
  // mixed_pixels on the same beam: the weighted mean, in mid-air.
  const auto mixed = run_stage(*make_mixed_pixels_stage(0.0025, 7, scanner_with().optics, false), step);
  ASSERT_TRUE(mixed.has_value());
  EXPECT_GT(mixed->range_m, 2.9);
  EXPECT_LT(mixed->range_m, 4.0);
}

TEST(Waveform, DepthStepSwept_EveryRangeOnASurface) {
  const DepthStepCaster step(2.8, 4.18, 0.7);
  const auto stage = make_waveform_stage(scanner_with(), false);
  for (int i = -10; i <= 10; ++i) {
    const double offset_rad = i * 0.25e-3;  // across the 1.25 mrad half-angle and beyond
    const auto beam = run_stage(*stage, step, Eigen::Vector3d(1.0, std::tan(offset_rad), 0.0));
    ASSERT_TRUE(beam.has_value()) << i;
    const double along_x = beam->range_m / std::sqrt(1.0 + std::tan(offset_rad) * std::tan(offset_rad));
    const bool on_near = std::abs(along_x - 2.8) < 0.01;
    const bool on_far = std::abs(along_x - 4.18) < 0.01;
    EXPECT_TRUE(on_near || on_far) << i << ": " << beam->range_m;
  }
}

// A wall slanted by `incidence` about the vertical axis, 5 m away along the beam.
PlaneCaster slanted_wall(double incidence_rad) {
  return PlaneCaster(Eigen::Vector3d(std::cos(incidence_rad), std::sin(incidence_rad), 0.0), 5.0 * std::cos(incidence_rad), 1.0);
}

TEST(Waveform, SlantedSurface_PulseStretchesLowerAndWider) {
  scene::ScannerConfig scanner = scanner_with();
  scanner.beam_divergence_rad = 0.02;  // a wide beam makes the stretch large against the pulse
  scanner.mixed_pixel_subrays = 37;
  const auto stage = make_waveform_stage(scanner, false);
  const auto head_on = run_stage(*stage, slanted_wall(0.0));
  const auto slanted = run_stage(*stage, slanted_wall(80.0 * kDeg));
  ASSERT_TRUE(head_on && slanted);
  EXPECT_NEAR(head_on->range_m, 5.0, 1e-3);
  // The footprint spans 5 m * 0.02 * tan(80 deg) = 0.57 m of range, about a pulse's FWHM: the
  // pulses no longer add up at one range, the hump is lower than the power received (without
  // incidence both walls return the same power), and its peak stays inside the footprint.
  EXPECT_LT(*slanted->irradiance, 0.9 * *head_on->irradiance);
  EXPECT_NEAR(slanted->range_m, 5.0, 0.29);
}

TEST(Waveform, SurfacesCloserThanThePulse_MergeAndTheRangeWalksToTheStronger) {
  // 0.2 m apart, a third of the pulse's FWHM: one hump. The centre and three sub-rays (y >= 0)
  // see the near surface, three the far one.
  const DepthStepCaster close_step(5.0, 5.2, 0.7);
  const auto beam = run_stage(*make_waveform_stage(scanner_with(scene::EchoDetection::last), false), close_step);
  ASSERT_TRUE(beam.has_value());
  EXPECT_GT(beam->range_m, 5.0 + 0.01);  // pulled off the near surface ...
  EXPECT_LT(beam->range_m, 5.1);         // ... but nearer it than the far one (4 sub-rays of 7)
}

TEST(Waveform, CastsTheFootprintsSubrays) {
  scene::ScannerConfig scanner = scanner_with();
  scanner.mixed_pixel_subrays = 19;
  const auto stage = make_waveform_stage(scanner, false);
  const PlaneCaster wall(Eigen::Vector3d::UnitX(), 4.0, 1.0);
  BeamState beam;
  beam.ray = raycast::Ray{.origin_m = Eigen::Vector3d::Zero(), .direction = Eigen::Vector3d::UnitX(), .max_range_m = 31.0};
  BeamCounters counters;
  stage->apply(beam, BeamContext{.caster = wall}, counters);
  EXPECT_EQ(counters.rays_cast, 19u);
  EXPECT_EQ(counters.random_draws, 0u);
}

TEST(EffectPipeline, Waveform_ReplacesMixedPixels) {
  scene::EffectSet effects;
  for (scene::Effect effect : {scene::Effect::mixed_pixels, scene::Effect::waveform, scene::Effect::intensity})
    effects.add(effect);
  EXPECT_EQ(EffectPipeline::build(scene::ScannerConfig{}, effects).stage_names(),
            (std::vector<std::string_view>{"waveform", "intensity"}));
}

}  // namespace
}  // namespace ldoem::sensor
