// The tilt history the motor models write themselves: exact answers at past times, nothing
// recorded while nothing moves, bounded memory.
#include <ldoem/motor/dynamic_tilt_motor.hpp>
#include <ldoem/motor/ideal_tilt_motor.hpp>
#include <ldoem/motor/tilt_history.hpp>

#include <gtest/gtest.h>

#include "tilt_pulses.hpp"

namespace ldoem::motor {
namespace {

using namespace std::chrono_literals;

using test::kConfig;
using test::kFullStep;

TEST(TiltHistory, IdealMotor_RecordsOnlyAtPulsesAndAnswersThePast) {
  TiltHistory history;
  IdealTiltMotor motor(kConfig);
  motor.attach_history(&history);
  motor.on_step_pulse(10ms, +1, false);
  motor.on_step_pulse(20ms, +1, false);
  motor.advance_to(10s);  // an idle stretch: nothing recorded, nothing sampled
  EXPECT_LE(history.size(), 5u);
  EXPECT_EQ(history.tilt_at(5ms, motor.tilt_rad()), 0.0);
  EXPECT_EQ(history.tilt_at(15ms, motor.tilt_rad()), kFullStep);
  EXPECT_EQ(history.tilt_at(25ms, motor.tilt_rad()), 2 * kFullStep);
  EXPECT_EQ(history.tilt_at(9s, motor.tilt_rad()), 2 * kFullStep);
}

TEST(TiltHistory, DynamicMotor_RecordsWhileMovingNotWhileResting) {
  TiltHistory history;
  DynamicTiltMotor motor(kConfig);
  motor.attach_history(&history);
  motor.on_step_pulse(1s, +1, false);  // at rest until then
  motor.advance_to(1100ms);
  const std::size_t after_move = history.size();
  EXPECT_GT(after_move, 10u);  // one record per 1 ms world step while it moved
  motor.advance_to(1h);
  EXPECT_LE(history.size(), after_move + 1);  // settled: no more work, no more records
  EXPECT_EQ(history.tilt_at(500ms, motor.tilt_rad()), 0.0);  // still at rest before the pulse
  EXPECT_NEAR(history.tilt_at(2s, motor.tilt_rad()), kFullStep, 1e-6 * kFullStep);
}

TEST(TiltHistory, OldRecords_AreDroppedBeyondTheSpan) {
  TiltHistory history(100ms);
  for (int i = 0; i < 1000; ++i) history.record(SimTime(i * 1ms), i * 1e-3);
  EXPECT_LE(history.size(), 102u);
  EXPECT_NEAR(history.tilt_at(950ms, 0.0), 0.95, 1e-12);
}

// Issue 11 #6: an LPT flood while a virtual clock stands still is any number of pulses at one
// instant; the history keeps the way in and the way out of that instant, not every pulse.
TEST(TiltHistory, PulsesAtOneInstant_KeepTwoRecords) {
  TiltHistory history;
  IdealTiltMotor motor(kConfig);
  motor.attach_history(&history);
  motor.on_step_pulse(10ms, +1, false);
  for (int i = 0; i < 100'000; ++i) {
    motor.on_step_pulse(20ms, +1, false);
    motor.on_step_pulse(20ms, -1, false);
  }
  motor.on_step_pulse(20ms, +1, false);
  EXPECT_LE(history.size(), 5u);
  EXPECT_EQ(history.tilt_at(15ms, motor.tilt_rad()), kFullStep);  // before the burst: one step
  EXPECT_EQ(history.tilt_at(20ms, motor.tilt_rad()), 2 * kFullStep);  // after it: one more
}

// A flood over distinct instants inside the span (a tiny --time-scale) is bounded by count.
TEST(TiltHistory, FloodOverDistinctInstants_IsBoundedByCount) {
  TiltHistory history(std::chrono::hours(1), 1000);
  for (int i = 0; i < 100'000; ++i) history.record(SimTime(i), (i % 3) * 1e-3);
  EXPECT_EQ(history.size(), 1000u);
  EXPECT_NEAR(history.tilt_at(SimTime(99'999), 7.0), 7.0, 0.0);  // the newest end answers "now"
  EXPECT_NEAR(history.tilt_at(SimTime(99'500), 0.0), (99'500 % 3) * 1e-3, 1e-15);
}

}  // namespace
}  // namespace ldoem::motor
