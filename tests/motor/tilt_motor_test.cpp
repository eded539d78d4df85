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
using test::kHalfStep;
using test::pulse_train;

// Sweeps between -amplitude and +amplitude full steps around home, `total_steps` pulses in all,
// ending at home (total_steps must be a multiple of 4 * amplitude).
SimTime sweep_and_return(TiltMotor& motor, std::int64_t total_steps, std::int64_t amplitude, double rate_hz) {
  SimTime at{0};
  for (std::int64_t done = 0; done < total_steps; done += 4 * amplitude) {
    at = pulse_train(motor, at, amplitude, +1, rate_hz);
    at = pulse_train(motor, at, 2 * amplitude, -1, rate_hz);
    at = pulse_train(motor, at, amplitude, +1, rate_hz);
  }
  return at;
}

TEST(HalfStep, DefaultGear_Is0045DegreesAtTheOutput) { EXPECT_NEAR(kHalfStep, 0.045 * kDeg, 1e-15); }

TEST(IdealTiltMotor, OneFullStep_Exactly009Degrees) {
  IdealTiltMotor motor(kConfig);
  motor.on_step_pulse(0ms, +1, false);
  EXPECT_DOUBLE_EQ(motor.tilt_rad(), 0.09 * kDeg);
  EXPECT_EQ(motor.commanded_steps(), 2);
}

TEST(IdealTiltMotor, OneHalfStepDown_ExactlyMinus0045Degrees) {
  IdealTiltMotor motor(kConfig);
  motor.on_step_pulse(0ms, -1, true);
  EXPECT_DOUBLE_EQ(motor.tilt_rad(), -0.045 * kDeg);
  EXPECT_EQ(motor.commanded_steps(), -1);
}

TEST(IdealTiltMotor, ZeroDirection_Ignored) {
  IdealTiltMotor motor(kConfig);
  motor.on_step_pulse(0ms, 0, false);
  EXPECT_EQ(motor.commanded_steps(), 0);
  EXPECT_EQ(motor.tilt_rad(), 0.0);
}

TEST(IdealTiltMotor, MillionStepsUpAndDown_EndExactlyAtHome) {
  IdealTiltMotor motor(kConfig);
  const SimTime end = sweep_and_return(motor, 1'000'000, 500, 1000.0);
  motor.advance_to(end);
  EXPECT_EQ(motor.commanded_steps(), 0);
  EXPECT_EQ(motor.tilt_rad(), 0.0) << motor.dump();
}

TEST(IdealTiltMotor, HardStop_LosesStepsThenComesBackAtOnce) {
  IdealTiltMotor motor(kConfig);
  // 90 deg = 1000 full steps; send 1100.
  SimTime at = pulse_train(motor, 0ms, 1100, +1, 1000.0);
  EXPECT_NEAR(motor.tilt_rad(), 90 * kDeg, 1e-12);
  EXPECT_EQ(motor.commanded_steps(), 2200);
  pulse_train(motor, at, 10, -1, 1000.0);
  EXPECT_NEAR(motor.tilt_rad(), 89.1 * kDeg, 1e-12) << motor.dump();
}

TEST(MakeTiltMotor, MotorDynamicsNamed_DynamicElseIdeal) {
  scene::Scene scene;
  EXPECT_NE(dynamic_cast<IdealTiltMotor*>(make_tilt_motor(scene).get()), nullptr);
  scene.effects.add(scene::Effect::motor_dynamics);
  EXPECT_NE(dynamic_cast<DynamicTiltMotor*>(make_tilt_motor(scene).get()), nullptr);
}

TEST(TiltDriveLimits, DefaultsFromTheTorqueLaw) {
  const TiltDriveLimits limits = tilt_drive_limits(kConfig);
  EXPECT_NEAR(limits.stall_torque_n_m, 20 * 0.3 * 12 / 2.0, 1e-12);   // G k_t V / R
  EXPECT_NEAR(limits.no_load_speed_rad_s, 12 / (20 * 0.3), 1e-12);     // V / (G k_v)
  EXPECT_NEAR(limits.total_inertia_kg_m2, 0.05 + 400 * 5e-5, 1e-12);
  EXPECT_EQ(limits.rated_half_step_rate_hz, 1273.0);                   // 1 rad/s / 0.045 deg
}

// The rated full-step rate of the tests: half the no-load speed, in full steps per second (636).
double rated_full_step_rate_hz() { return std::floor(tilt_drive_limits(kConfig).rated_half_step_rate_hz / 2); }

TEST(DynamicTiltMotor, OneStep_SettlesOnIt) {
  DynamicTiltMotor motor(kConfig);
  motor.on_step_pulse(0ms, +1, false);
  motor.advance_to(200ms);
  EXPECT_NEAR(motor.tilt_rad(), kFullStep, 1e-6 * kFullStep) << motor.dump();
  EXPECT_EQ(motor.lost_half_steps(), 0);
}

TEST(DynamicTiltMotor, RatedRateTrain_FollowsWithoutLoss) {
  DynamicTiltMotor motor(kConfig);
  const SimTime end = pulse_train(motor, 0ms, 500, +1, rated_full_step_rate_hz());
  motor.advance_to(end + 500ms);
  EXPECT_EQ(motor.lost_half_steps(), 0) << motor.dump();
  EXPECT_NEAR(motor.tilt_rad(), 500 * kFullStep, kHalfStep) << motor.dump();
}

TEST(DynamicTiltMotor, HundredThousandStepsAtRatedRate_EndWithinOneStepOfHome) {
  DynamicTiltMotor motor(kConfig);
  const SimTime end = sweep_and_return(motor, 100'000, 500, rated_full_step_rate_hz());
  motor.advance_to(end + 1s);
  EXPECT_EQ(motor.commanded_steps(), 0);
  EXPECT_EQ(motor.lost_half_steps(), 0) << motor.dump();
  EXPECT_LE(std::abs(motor.tilt_rad()), kFullStep) << motor.dump();
}

TEST(DynamicTiltMotor, MillionStepsAtRatedRate_EndWithinOneStepOfHome) {
  DynamicTiltMotor motor(kConfig);
  const SimTime end = sweep_and_return(motor, 1'000'000, 500, rated_full_step_rate_hz());
  motor.advance_to(end + 1s);
  EXPECT_EQ(motor.commanded_steps(), 0);
  EXPECT_EQ(motor.lost_half_steps(), 0) << motor.dump();
  EXPECT_LE(std::abs(motor.tilt_rad()), kFullStep) << motor.dump();
}

TEST(DynamicTiltMotor, OverSpeedTrain_LosesStepsAndReportsThePhysicalTilt) {
  DynamicTiltMotor motor(kConfig);
  const TiltDriveLimits limits = tilt_drive_limits(kConfig);
  // 3000 full steps/s = 4.7 rad/s, beyond the no-load speed of 2 rad/s: the torque cannot follow.
  const SimTime end = pulse_train(motor, 0ms, 600, +1, 3000.0);
  motor.advance_to(end + 500ms);
  const double commanded_rad = static_cast<double>(motor.commanded_steps()) * kHalfStep;
  EXPECT_GT(motor.lost_half_steps(), 0) << motor.dump();
  EXPECT_EQ(motor.lost_half_steps() % 8, 0);  // lost a whole number of electrical cycles
  // The physical angle is what the field ended on, not the counter, and no more than the
  // no-load speed allows in the train's duration.
  EXPECT_NEAR(motor.tilt_rad(), static_cast<double>(motor.commanded_steps() - motor.lost_half_steps()) * kHalfStep,
              1e-6) << motor.dump();
  EXPECT_LT(motor.tilt_rad(), commanded_rad - kFullStep);
  // no-load travel during the train, plus the most the field may lead the shaft (pull-out lag).
  EXPECT_LE(motor.tilt_rad(),
            limits.no_load_speed_rad_s * std::chrono::duration<double>(end).count() + 2 * kFullStep);
  EXPECT_GT(motor.tilt_rad(), 0.0);
}

TEST(DynamicTiltMotor, Settled_NoDriftAndNoWorkOverAnHour) {
  DynamicTiltMotor motor(kConfig);
  const SimTime end = pulse_train(motor, 0ms, 100, +1, rated_full_step_rate_hz());
  motor.advance_to(end + 1s);
  const double settled_tilt = motor.tilt_rad();
  const std::uint64_t steps_so_far = motor.world_steps_taken();
  motor.advance_to(end + 3600s);
  EXPECT_EQ(motor.tilt_rad(), settled_tilt);
  EXPECT_EQ(motor.world_steps_taken(), steps_so_far);
}

TEST(DynamicTiltMotor, SameTrain_BitIdenticalTilt) {
  DynamicTiltMotor first(kConfig);
  DynamicTiltMotor second(kConfig);
  for (DynamicTiltMotor* motor : {&first, &second}) {
    const SimTime end = pulse_train(*motor, 0ms, 300, +1, 2000.0, true);
    motor->advance_to(end + 5ms);
  }
  EXPECT_EQ(first.tilt_rad(), second.tilt_rad());
}

TEST(DynamicTiltMotor, HardStop_HoldsThePlate) {
  scene::TiltMotorConfig config = kConfig;
  config.max_tilt_deg = 5.0;
  DynamicTiltMotor motor(config);
  const SimTime end = pulse_train(motor, 0ms, 100, +1, 200.0);  // 9 deg commanded
  motor.advance_to(end + 1s);
  EXPECT_LE(motor.tilt_rad(), 5.0 * kDeg + 1e-3) << motor.dump();
  EXPECT_GT(motor.lost_half_steps(), 0);
}

TEST(DynamicTiltMotor, Dump_NamesTheCounters) {
  DynamicTiltMotor motor(kConfig);
  const std::string dump = motor.dump();
  EXPECT_NE(dump.find("commanded_half_steps: 0"), std::string::npos);
  EXPECT_NE(dump.find("lost_half_steps: 0"), std::string::npos);
}

}  // namespace
}  // namespace ldoem::motor
