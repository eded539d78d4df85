// D9 head_dynamics in the plant: the LD fires on encoder ticks, so the ripple moves the time each
// point fires (motor::HeadRippleTrack, the benchmarks' model too), never its angle. The time
// reaches the range through the point's tilt under sweep_motion. Without the effect nothing
// changes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ldoem/motor/head_ripple_track.hpp"
#include "ldoem/motor/ideal_tilt_motor.hpp"
#include "ldoem/plant/scene_ports.hpp"
#include "ldoem/raycast/ode_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::plant {
namespace {

using namespace std::chrono_literals;

// A large ripple: 2 % of 10 Hz at 5 Hz: points fire up to 2 A / (Omega omega) = 1.3 ms early or late.
scene::HeadConfig large_ripple() {
  scene::HeadConfig head;
  head.ripple_fraction = 0.02;
  head.ripple_frequency_hz = 5.0;
  return head;
}

constexpr std::uint16_t kSixtyDegrees = 960;  // ticks

// A wall 5 m ahead seen at 60 deg, beams every 10 ms after the head holds its speed; the plate
// climbs one full step (0.09 deg) every 0.1 ms during them, so the tilt, and with it the range
// 5 m / (cos 60 deg cos tilt), depends on when a point fires.
class SlantedWall : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = scene::load_scene_from_string(
        "objects:\n  - name: wall\n    box: {size_m: [0.2, 40, 40]}\n    pose: {position_m: [5.1, 0, 0]}\n",
        "wall.yaml");
    ASSERT_TRUE(loaded) << loaded.error().message();
    scene_ = std::move(*loaded);
    world_ = std::make_unique<raycast::OdeWorld>(scene_);
    caster_ = std::make_unique<raycast::OdeRayCaster>(*world_);
    sensor_ = std::make_unique<sensor::SensorModel>(scene_, *caster_);
    for (int i = 0; i < 5; ++i) beams_.push_back(control::BeamQuery{3s + i * 10ms, kSixtyDegrees, kSixtyDegrees});
  }

  // A fresh plate climbing from 2.99 s to 3.05 s, and one revolution starting at 2.95 s.
  std::vector<control::BeamReturn> measure(const motor::HeadRippleTrack* head, bool sweep_motion,
                                           std::unique_ptr<TiltPlate>* plate_out = nullptr) {
    auto plate = std::make_unique<TiltPlate>(std::make_unique<motor::IdealTiltMotor>(scene_.scanner.tilt_motor));
    for (SimTime at = 2990ms; at < 3050ms; at += 100us) {
      plate->on_step(protocol::StepPulse{at, protocol::TiltDirection::increasing, protocol::StepMode::full_step});
    }
    SceneMeasurement measurement(*sensor_, *plate, sweep_motion, head);
    std::vector<control::BeamReturn> returns(beams_.size());
    measurement.measure({1, 2950ms}, beams_, returns);
    if (plate_out) *plate_out = std::move(plate);
    return returns;
  }

  scene::Scene scene_;
  std::unique_ptr<raycast::OdeWorld> world_;
  std::unique_ptr<raycast::OdeRayCaster> caster_;
  std::unique_ptr<sensor::SensorModel> sensor_;
  std::vector<control::BeamQuery> beams_;
};

TEST_F(SlantedWall, WithoutSweepMotion_TheRippleChangesNoRange) {
  motor::HeadRippleTrack head(large_ripple());
  head.set_target(SimTime::zero(), 10.0);
  // The angle stays nominal and the tilt is frozen at the revolution's start: nothing moves.
  EXPECT_EQ(measure(&head, false), measure(nullptr, false));
}

TEST_F(SlantedWall, WithSweepMotion_EachPointTakesTheTiltAtItsShiftedTime) {
  motor::HeadRippleTrack head(large_ripple());
  head.set_target(SimTime::zero(), 10.0);
  std::unique_ptr<TiltPlate> plate;
  const auto rippled = measure(&head, true, &plate);
  const auto nominal = measure(nullptr, true);
  int shifted = 0;
  for (std::size_t i = 0; i < beams_.size(); ++i) {
    const SimTime fires = head.fire_time(2950ms, beams_[i].time);
    if (std::chrono::abs(fires - beams_[i].time) > 50us) ++shifted;
    const double tilt = plate->tilt_at(fires);
    const double expected_m = 5.0 / (std::cos(std::numbers::pi / 3) * std::cos(tilt));
    EXPECT_NEAR(rippled[i].distance_q8_m, 256.0 * expected_m, 1.0) << i;
  }
  EXPECT_GE(shifted, 3);
  EXPECT_NE(rippled, nominal);
}

TEST_F(SlantedWall, HeadDynamicsWithoutRipple_IsByteIdenticalToNominal) {
  scene::HeadConfig still = large_ripple();
  still.ripple_fraction = 0.0;
  motor::HeadRippleTrack head(still);
  head.set_target(SimTime::zero(), 10.0);
  EXPECT_EQ(measure(&head, true), measure(nullptr, true));
}

}  // namespace
}  // namespace ldoem::plant
