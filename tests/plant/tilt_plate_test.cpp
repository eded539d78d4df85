// D8 drive board and the tilt history the sensor model reads (D9 sweep_motion or frozen tilt).
#include <gtest/gtest.h>

#include <numbers>

#include "ldoem/plant/tilt_plate.hpp"
#include "ldoem/motor/ideal_tilt_motor.hpp"

namespace ldoem::plant {
namespace {

using namespace std::chrono_literals;

constexpr double kFullStepRad = 0.09 * std::numbers::pi / 180.0;  // D8: 1.8 deg / 20

TiltPlate ideal_track() { return TiltPlate(std::make_unique<motor::IdealTiltMotor>(scene::TiltMotorConfig{})); }

// Writes `steps` clock pulses (low, high) with the given DIR/MODE bits, 1 ms apart.
void pulse(StepperDriveBoard& board, SimTime& at, int steps, std::uint8_t bits) {
  for (int i = 0; i < steps; ++i) {
    board.on_register_write(at, bits);
    board.on_register_write(at + 500us, static_cast<std::uint8_t>(bits | protocol::kLptClockBit));
    at += 1ms;
  }
}

TEST(StepperDriveBoard, RisingClockEdgesWithDirectionSet_RaiseTheTiltOneFullStepEach) {
  TiltPlate track = ideal_track();
  StepperDriveBoard board(track);
  SimTime at = 0s;
  pulse(board, at, 10, protocol::kLptDirectionBit);
  EXPECT_EQ(board.steps_seen(), 10u);
  EXPECT_NEAR(track.tilt_now(), 10 * kFullStepRad, 1e-12);
}

TEST(StepperDriveBoard, DirectionClearAndHalfStepMode_LowerByHalfSteps) {
  TiltPlate track = ideal_track();
  StepperDriveBoard board(track);
  SimTime at = 0s;
  pulse(board, at, 4, protocol::kLptModeBit);
  EXPECT_NEAR(track.tilt_now(), -4 * kFullStepRad / 2, 1e-12);
}

TEST(StepperDriveBoard, RepeatedHighWrites_AreOneEdge) {
  TiltPlate track = ideal_track();
  StepperDriveBoard board(track);
  board.on_register_write(0s, 0x03);
  board.on_register_write(1ms, 0x03);
  board.on_register_write(2ms, 0xFB & 0x03);  // ignored bits (D8) do not make edges
  EXPECT_EQ(board.steps_seen(), 1u);
}

TEST(StepperDriveBoard, GpioLineChanges_BuildTheSameRegister) {
  TiltPlate track = ideal_track();
  StepperDriveBoard board(track);
  board.on_line_change(0s, protocol::kLptDirectionBit, true);
  board.on_line_change(1ms, protocol::kLptClockBit, true);
  board.on_line_change(2ms, protocol::kLptClockBit, false);
  board.on_line_change(3ms, protocol::kLptClockBit, true);
  EXPECT_EQ(board.steps_seen(), 2u);
  EXPECT_NEAR(track.tilt_now(), 2 * kFullStepRad, 1e-12);
}

TEST(TiltPlate, TiltAtAPastTime_IsTheTiltThen) {
  TiltPlate track = ideal_track();
  StepperDriveBoard board(track);
  board.on_register_write(10ms, 0x03);  // one step up at 10 ms
  board.on_register_write(20ms, 0x01);
  board.on_register_write(30ms, 0x03);  // and another at 30 ms
  track.advance_to(50ms);
  EXPECT_EQ(track.tilt_at(5ms), 0.0);
  EXPECT_NEAR(track.tilt_at(15ms), kFullStepRad, 1e-12);
  EXPECT_NEAR(track.tilt_at(29ms), kFullStepRad, 1e-12);
  EXPECT_NEAR(track.tilt_at(31ms), 2 * kFullStepRad, 1e-12);
  EXPECT_NEAR(track.tilt_at(60ms), 2 * kFullStepRad, 1e-12);
}

TEST(TiltPlate, LongIdleStretch_KeepsTheHistorySmallAndAnswersRight) {
  TiltPlate track = ideal_track();
  StepperDriveBoard board(track);
  board.on_register_write(1ms, 0x03);
  track.advance_to(100s);
  EXPECT_NEAR(track.tilt_at(99s), kFullStepRad, 1e-12);
  // Nothing samples the plate on a clock (D9): 100 s idle added no record.
  EXPECT_LE(track.history_size(), 3u);
}

}  // namespace
}  // namespace ldoem::plant
