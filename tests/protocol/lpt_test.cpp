// Pseudo-LPT register (D8): every bit, the drive-train constants, and step edges.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <optional>

#include "ldoem/protocol/lpt.hpp"

namespace ldoem::protocol {
namespace {

using std::chrono::milliseconds;

TEST(LptRegister, AllZero_DecreasingClockLowFullStep) {
  const LptRegister lpt = decode_lpt(0x00);
  EXPECT_EQ(lpt.direction, TiltDirection::decreasing);
  EXPECT_FALSE(lpt.clock_high);
  EXPECT_EQ(lpt.mode, StepMode::full_step);
}

TEST(LptRegister, Data0_DirectionIncreasingOnly) {
  EXPECT_EQ(decode_lpt(0x01), (LptRegister{TiltDirection::increasing, false, StepMode::full_step}));
}

TEST(LptRegister, Data1_ClockHighOnly) {
  EXPECT_EQ(decode_lpt(0x02), (LptRegister{TiltDirection::decreasing, true, StepMode::full_step}));
}

TEST(LptRegister, Data2_HalfStepOnly) {
  EXPECT_EQ(decode_lpt(0x04), (LptRegister{TiltDirection::decreasing, false, StepMode::half_step}));
}

TEST(LptRegister, Data3To7_Ignored) {
  for (int bit = 3; bit < 8; ++bit) {
    EXPECT_EQ(decode_lpt(static_cast<std::uint8_t>(1u << bit)), decode_lpt(0x00)) << "bit " << bit;
  }
  EXPECT_EQ(decode_lpt(0xFF), decode_lpt(0x07));
}

TEST(LptRegister, EncodeDecode_RoundTripForEveryByte) {
  for (int value = 0; value < 256; ++value) {
    const auto byte = static_cast<std::uint8_t>(value);
    EXPECT_EQ(encode_lpt(decode_lpt(byte)), byte & kLptUsedBits) << value;
  }
  EXPECT_EQ(encode_lpt({TiltDirection::increasing, true, StepMode::half_step}), 0x07);
}

TEST(LptDriveTrain, OutputShaftPerStep_FullAndHalf) {
  EXPECT_DOUBLE_EQ(kMotorFullStepDeg, 1.8);
  EXPECT_DOUBLE_EQ(kTiltGearRatio, 20.0);
  EXPECT_DOUBLE_EQ(output_shaft_deg_per_step(StepMode::full_step), 0.09);
  EXPECT_DOUBLE_EQ(output_shaft_deg_per_step(StepMode::half_step), 0.045);
  // One output-shaft turn: 20 motor turns of 200 full or 400 half steps.
  EXPECT_NEAR(kTiltGearRatio * kMotorFullStepsPerTurn * kOutputShaftFullStepDeg, 360.0, 1e-9);
  EXPECT_NEAR(kTiltGearRatio * kMotorHalfStepsPerTurn * kOutputShaftHalfStepDeg, 360.0, 1e-9);
}

TEST(LptStepEdgeDetector, RisingClock_OneStepWithTimeDirectionMode) {
  StepEdgeDetector detector;
  EXPECT_FALSE(detector.on_write(milliseconds(1), 0x01).has_value());  // direction only
  const std::optional<StepPulse> pulse = detector.on_write(milliseconds(2), 0x03);
  ASSERT_TRUE(pulse.has_value());
  EXPECT_EQ(*pulse, (StepPulse{milliseconds(2), TiltDirection::increasing, StepMode::full_step}));
  EXPECT_DOUBLE_EQ(pulse->tilt_change_deg(), 0.09);
  EXPECT_EQ(detector.steps_seen(), 1u);
}

TEST(LptStepEdgeDetector, FallingClock_NoStep) {
  StepEdgeDetector detector;
  ASSERT_TRUE(detector.on_write(milliseconds(1), 0x02).has_value());
  EXPECT_FALSE(detector.on_write(milliseconds(2), 0x00).has_value());
  EXPECT_EQ(detector.steps_seen(), 1u);
}

TEST(LptStepEdgeDetector, RepeatedSameValue_NoFurtherStep) {
  StepEdgeDetector detector;
  ASSERT_TRUE(detector.on_write(milliseconds(1), 0x02).has_value());
  for (int i = 0; i < 5; ++i) {
    EXPECT_FALSE(detector.on_write(milliseconds(2 + i), 0x02).has_value());
  }
  EXPECT_EQ(detector.steps_seen(), 1u);
}

TEST(LptStepEdgeDetector, DirectionOrModeChangeWhileClockHigh_NoStep) {
  StepEdgeDetector detector;
  ASSERT_TRUE(detector.on_write(milliseconds(1), 0x02).has_value());
  EXPECT_FALSE(detector.on_write(milliseconds(2), 0x03).has_value());
  EXPECT_FALSE(detector.on_write(milliseconds(3), 0x07).has_value());
  EXPECT_FALSE(detector.on_write(milliseconds(4), 0xFA).has_value());  // ignored bits too
}

TEST(LptStepEdgeDetector, ClockHighAtStart_NoStepUntilNextRise) {
  StepEdgeDetector detector(0x02);
  EXPECT_FALSE(detector.on_write(milliseconds(1), 0x02).has_value());
  EXPECT_FALSE(detector.on_write(milliseconds(2), 0x00).has_value());
  EXPECT_TRUE(detector.on_write(milliseconds(3), 0x02).has_value());
}

TEST(LptStepEdgeDetector, DirectionDown_NegativeTiltChange) {
  StepEdgeDetector detector;
  const std::optional<StepPulse> pulse = detector.on_write(milliseconds(1), 0x02);
  ASSERT_TRUE(pulse.has_value());
  EXPECT_EQ(pulse->direction, TiltDirection::decreasing);
  EXPECT_DOUBLE_EQ(pulse->tilt_change_deg(), -0.09);
}

TEST(LptStepEdgeDetector, ModeSwitchMidRun_StepsTakeModeOfTheirEdge) {
  StepEdgeDetector detector;
  // Three full steps up, then switch to half step (clock low) and do two more.
  const std::uint8_t writes[] = {0x01, 0x03, 0x01, 0x03, 0x01, 0x03, 0x01,
                                 0x05, 0x07, 0x05, 0x07, 0x05};
  double tilt_deg = 0.0;
  int full_steps = 0;
  int half_steps = 0;
  for (std::size_t i = 0; i < std::size(writes); ++i) {
    const std::optional<StepPulse> pulse = detector.on_write(milliseconds(i), writes[i]);
    if (!pulse) {
      continue;
    }
    tilt_deg += pulse->tilt_change_deg();
    (pulse->mode == StepMode::full_step ? full_steps : half_steps) += 1;
  }
  EXPECT_EQ(full_steps, 3);
  EXPECT_EQ(half_steps, 2);
  EXPECT_NEAR(tilt_deg, 3 * 0.09 + 2 * 0.045, 1e-12);
  EXPECT_EQ(detector.current(), decode_lpt(0x05));
}

TEST(LptStepEdgeDetector, ModeSwitchOnTheRisingWrite_UsesNewMode) {
  StepEdgeDetector detector;
  const std::optional<StepPulse> pulse = detector.on_write(milliseconds(1), 0x06);
  ASSERT_TRUE(pulse.has_value());
  EXPECT_EQ(pulse->mode, StepMode::half_step);
}

}  // namespace
}  // namespace ldoem::protocol
