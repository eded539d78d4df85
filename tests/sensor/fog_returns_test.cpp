// D13 atmosphere with fog_returns: fog's own backscatter is one more pulse in the received
// waveform at fog_overlap_m, so in thick fog the first echo is the fog, the last is the wall,
// and in clear air the fog pulse stays under the threshold.
#include "fake_casters.hpp"

#include <ldoem/sensor/sensor_model.hpp>

#include <gtest/gtest.h>

namespace ldoem::sensor {
namespace {

using scene::Effect;

scene::Scene foggy_scene(double visibility_m, scene::EchoDetection detection, bool fog_returns = true) {
  scene::Scene scene;
  scene.scanner.max_range_m = 250.0;
  scene.effects.add(Effect::waveform);
  scene.effects.add(Effect::atmosphere);
  scene.scanner.waveform.detection = detection;
  scene.scanner.atmosphere.visibility_m = visibility_m;
  scene.scanner.atmosphere.fog_returns = fog_returns;
  return scene;
}

double straight_range_m(const scene::Scene& scene, double wall_m) {
  const testing::PlaneCaster wall(Eigen::Vector3d::UnitX(), wall_m, 1.0);
  const SensorModel model(scene, wall);
  const std::vector<BeamRequest> beams{{.head_angle_rad = 0.0, .tilt_rad = 0.0, .beam_index = 0}};
  std::vector<BeamSample> samples(1);
  model.measure(0, beams, samples);
  return samples[0].distance / kDistanceUnitsPerMetre;
}

TEST(FogReturns, ThickFog_FirstEchoIsTheFogAtTheOverlapRange) {
  const double first = straight_range_m(foggy_scene(100.0, scene::EchoDetection::first), 20.0);
  EXPECT_NEAR(first, 1.0, 0.01);
}

TEST(FogReturns, ThickFog_LastEchoIsStillTheWall) {
  EXPECT_NEAR(straight_range_m(foggy_scene(100.0, scene::EchoDetection::last), 20.0), 20.0, 0.01);
}

TEST(FogReturns, ThickFog_FogIsStrongerThanAnAttenuatedWall) {
  EXPECT_NEAR(straight_range_m(foggy_scene(100.0, scene::EchoDetection::strongest), 20.0), 1.0, 0.01);
}

TEST(FogReturns, Off_TheFirstEchoIsTheWall) {
  EXPECT_NEAR(straight_range_m(foggy_scene(100.0, scene::EchoDetection::first, false), 20.0), 20.0, 0.01);
}

TEST(FogReturns, ClearAir_FogPulseStaysBelowTheThreshold) {
  EXPECT_NEAR(straight_range_m(foggy_scene(100'000.0, scene::EchoDetection::first), 20.0), 20.0, 0.01);
}

TEST(FogReturns, OverlapRange_MovesTheFalseEcho) {
  scene::Scene scene = foggy_scene(100.0, scene::EchoDetection::first);
  scene.scanner.atmosphere.fog_overlap_m = 2.5;
  EXPECT_NEAR(straight_range_m(scene, 20.0), 2.5, 0.01);
}

}  // namespace
}  // namespace ldoem::sensor
