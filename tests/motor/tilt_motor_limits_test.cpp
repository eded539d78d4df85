// The tilt motor at the edges of its settings: a coarse world step (sub-stepped, so no step is
// lost that a finer step keeps) and hard stops near +-180 deg, where the hinge angle wraps.
#include <ldoem/motor/dynamic_tilt_motor.hpp>
#include <ldoem/motor/ideal_tilt_motor.hpp>

#include <gtest/gtest.h>

#include <cmath>

#include "tilt_pulses.hpp"

namespace ldoem::motor {
namespace {

using namespace std::chrono_literals;

using test::kConfig;
using test::kDeg;
using test::kFullStep;
using test::pulse_train;

// The paper's timing (accuracy-vs-time): 120 full steps to the low apex at 500 /s, then 2 steps
// per 100 ms layer. Returns the time the last layer's move has long settled.
SimTime paper_moves(TiltMotor& motor, int layers) {
  SimTime at = pulse_train(motor, 0ms, 120, -1, 500.0) + 300ms;
  for (int layer = 0; layer < layers; ++layer) {
    pulse_train(motor, at, 2, +1, 500.0);
    at += 100ms;
  }
  return at + 500ms;
}

TEST(PhysicsSubsteps, SplitsOnlyStepsLongerThanOneMillisecond) {
  EXPECT_EQ(physics_substeps(1e-4), 1);
  EXPECT_EQ(physics_substeps(1e-3), 1);
  EXPECT_EQ(physics_substeps(2.5e-3), 3);
  EXPECT_EQ(physics_substeps(1e-2), 10);
}

TEST(DynamicTiltMotor, WorldStep1e2_PaperMoves_LoseNoStepAndEndOnTheGrid) {
  scene::TiltMotorConfig config = kConfig;
  config.world_step_s = 1e-2;
  DynamicTiltMotor motor(config);
  EXPECT_EQ(motor.substeps_per_world_step(), 10);
  const SimTime end = paper_moves(motor, 60);
  motor.advance_to(end);
  EXPECT_EQ(motor.lost_half_steps(), 0) << motor.dump();
  const double commanded_rad = static_cast<double>(motor.commanded_steps()) * half_step_rad(config);
  EXPECT_NEAR(commanded_rad, 0.0 * kDeg, 1e-12);  // 120 down, 60 x 2 up
  EXPECT_NEAR(motor.tilt_rad(), commanded_rad, 1e-3 * kDeg) << motor.dump();
}

TEST(DynamicTiltMotor, WorldStep1e2_IntegratesLikeWorldStep1e3) {
  scene::TiltMotorConfig fine = kConfig;
  scene::TiltMotorConfig coarse = kConfig;
  coarse.world_step_s = 1e-2;
  DynamicTiltMotor fine_motor(fine);
  DynamicTiltMotor coarse_motor(coarse);
  pulse_train(fine_motor, 0ms, 120, -1, 500.0);
  pulse_train(coarse_motor, 0ms, 120, -1, 500.0);
  // Ten 1 ms sub-steps per 10 ms world step: the same grid, so the same numbers, mid-move too.
  for (const SimTime at : {100ms, 200ms, 600ms}) {
    fine_motor.advance_to(at);
    coarse_motor.advance_to(at);
    EXPECT_EQ(coarse_motor.tilt_rad(), fine_motor.tilt_rad()) << at.count();
  }
  EXPECT_EQ(coarse_motor.lost_half_steps(), 0);
}

// Drives a motor with stops at +-179 deg up to 178.65 deg, then 20 steps into the stop, then
// the mirror image; the plate must stop at the stop, never wrap to the other side.
void hinge_near_half_turn(TiltMotor& motor) {
  SimTime at = pulse_train(motor, 0ms, 1985, +1, 400.0) + 1s;
  motor.advance_to(at);
  EXPECT_NEAR(motor.tilt_rad(), 1985 * kFullStep, 1e-3 * kDeg) << motor.dump();
  at = pulse_train(motor, at, 20, +1, 100.0) + 1s;
  motor.advance_to(at);
  EXPECT_LE(motor.tilt_rad(), 179.0 * kDeg + 0.05 * kDeg) << motor.dump();
  EXPECT_GE(motor.tilt_rad(), 178.5 * kDeg) << motor.dump();
  at = pulse_train(motor, at, 2 * 1985 + 60, -1, 400.0) + 2s;
  motor.advance_to(at);
  EXPECT_GE(motor.tilt_rad(), -179.0 * kDeg - 0.05 * kDeg) << motor.dump();
  EXPECT_LE(motor.tilt_rad(), -178.5 * kDeg) << motor.dump();
}

scene::TiltMotorConfig stops_at_179() {
  scene::TiltMotorConfig config = kConfig;
  config.min_tilt_deg = -179.0;
  config.max_tilt_deg = 179.0;
  return config;
}

TEST(IdealTiltMotor, StopsAtPlusMinus179_HoldThePlateWithoutWrapping) {
  IdealTiltMotor motor(stops_at_179());
  hinge_near_half_turn(motor);
}

TEST(DynamicTiltMotor, StopsAtPlusMinus179_HoldThePlateWithoutWrapping) {
  DynamicTiltMotor motor(stops_at_179());
  hinge_near_half_turn(motor);
}

}  // namespace
}  // namespace ldoem::motor
