// D9 head_dynamics: the speed ripple moves the angle each ray is cast at; the reported angles
// stay nominal. Without the effect nothing changes.
#include "ldoem/plant/head_ripple.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ldoem/plant/scene_ports.hpp"
#include "ldoem/motor/ideal_tilt_motor.hpp"
#include "ldoem/raycast/ode_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::plant {
namespace {

using namespace std::chrono_literals;

// A large ripple: 2 % of 10 Hz at 5 Hz, so the head runs up to 2 A / omega = 0.08 rad ahead.
scene::HeadConfig large_ripple() {
  scene::HeadConfig head;
  head.ripple_fraction = 0.02;
  head.ripple_frequency_hz = 5.0;
  return head;
}

TEST(HeadRipple, BeforeTheSpeedIsHeld_NoDeviation) {
  HeadRipple track(large_ripple());
  track.set_target(SimTime::zero(), 10.0);
  EXPECT_EQ(track.deviation_rad(500ms), 0.0);  // still spinning up (about 2 s, D7)
}

TEST(HeadRipple, HeldSpeed_DeviationFollowsTheRippleWithinItsBound) {
  const scene::HeadConfig head = large_ripple();
  HeadRipple track(head);
  track.set_target(SimTime::zero(), 10.0);
  const double amplitude = 2.0 * std::numbers::pi * 10.0 * head.ripple_fraction;
  const double bound = 2.0 * amplitude / (2.0 * std::numbers::pi * head.ripple_frequency_hz);
  double largest = 0.0;
  for (SimTime at = 3s; at < 4s; at += 5ms) {
    const double deviation = track.deviation_rad(at);
    EXPECT_GE(deviation, -1e-9);
    EXPECT_LE(deviation, bound + 1e-9);
    largest = std::max(largest, deviation);
  }
  EXPECT_GT(largest, 0.9 * bound);
}

TEST(HeadRipple, NewTarget_StartsFromNoDeviation) {
  HeadRipple track(large_ripple());
  track.set_target(SimTime::zero(), 10.0);
  ASSERT_NE(track.deviation_rad(3100ms), 0.0);
  track.set_target(3100ms, 0.0);
  EXPECT_NEAR(track.deviation_rad(3100ms), 0.0, 1e-12);
  EXPECT_NEAR(track.deviation_rad(3200ms), 0.0, 1e-12);  // stopping: no ripple until held again
}

// A wall 5 m ahead seen at 60 deg: slanted, so a small change of angle changes the range.
class SlantedWall : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = scene::load_scene_from_string(
        "objects:\n  - name: wall\n    box: {size_m: [0.2, 40, 6]}\n    pose: {position_m: [5.1, 0, 0]}\n",
        "wall.yaml");
    ASSERT_TRUE(loaded) << loaded.error().message();
    scene_ = std::move(*loaded);
    world_ = std::make_unique<raycast::OdeWorld>(scene_);
    caster_ = std::make_unique<raycast::OdeRayCaster>(*world_);
    sensor_ = std::make_unique<sensor::SensorModel>(scene_, *caster_);
    tilt_ = std::make_unique<TiltPlate>(std::make_unique<motor::IdealTiltMotor>(scene_.scanner.tilt_motor));
    // Beams at 60 deg (960 ticks) every 10 ms over one ripple period, after the speed is held.
    for (int i = 0; i < 20; ++i) {
      beams_.push_back(control::BeamQuery{3s + i * 10ms, 960, 960});
    }
  }

  std::vector<control::BeamReturn> measure(const HeadRipple* head) {
    SceneMeasurement measurement(*sensor_, *tilt_, false, head);
    std::vector<control::BeamReturn> returns(beams_.size());
    measurement.measure({1, SimTime(0)}, beams_, returns);
    return returns;
  }

  scene::Scene scene_;
  std::unique_ptr<raycast::OdeWorld> world_;
  std::unique_ptr<raycast::OdeRayCaster> caster_;
  std::unique_ptr<sensor::SensorModel> sensor_;
  std::unique_ptr<TiltPlate> tilt_;
  std::vector<control::BeamQuery> beams_;
};

TEST_F(SlantedWall, WithoutHeadDynamics_EveryRayAtItsNominalAngle) {
  const auto returns = measure(nullptr);
  for (const auto& sample : returns) {
    EXPECT_EQ(sample.distance_q8_m, 2560);  // 5 m / cos 60 deg = 10 m, exactly as before the effect
  }
}

TEST_F(SlantedWall, WithALargeRipple_RangesDepartWhereTheHeadRunsAhead) {
  HeadRipple head(large_ripple());
  head.set_target(SimTime::zero(), 10.0);
  const auto nominal = measure(nullptr);
  const auto rippled = measure(&head);
  int differing = 0;
  for (std::size_t i = 0; i < beams_.size(); ++i) {
    const double true_angle = std::numbers::pi / 3 + head.deviation_rad(beams_[i].time);
    EXPECT_NEAR(rippled[i].distance_q8_m, 256.0 * 5.0 / std::cos(true_angle), 1.0) << i;
    if (rippled[i].distance_q8_m != nominal[i].distance_q8_m) ++differing;
  }
  EXPECT_GT(differing, 10);
}

TEST_F(SlantedWall, HeadDynamicsWithoutRipple_IsByteIdenticalToNominal) {
  scene::HeadConfig still = large_ripple();
  still.ripple_fraction = 0.0;
  HeadRipple head(still);
  head.set_target(SimTime::zero(), 10.0);
  EXPECT_EQ(measure(&head), measure(nullptr));
}

}  // namespace
}  // namespace ldoem::plant
