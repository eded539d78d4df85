// Meaning of the pseudo-LPT data register that drives the tilt stepper's board (D8), and the
// pure detector that turns a sequence of register writes into step pulses. The emulator's pty
// and gpio back ends and the host driver's ppdev/pty writer all share this one definition.
#pragma once

#include <cstdint>
#include <optional>

#include "ldoem/base/sim_time.hpp"

namespace ldoem::protocol {

// D8 register bits. Bits 3..7 are ignored by the board.
inline constexpr std::uint8_t kLptDirectionBit = 0x01;  // DATA0: 1 = tilt angle grows
inline constexpr std::uint8_t kLptClockBit = 0x02;      // DATA1: one step per rising edge
inline constexpr std::uint8_t kLptModeBit = 0x04;       // DATA2: 0 full step, 1 half step
inline constexpr std::uint8_t kLptUsedBits = kLptDirectionBit | kLptClockBit | kLptModeBit;

// D8 drive train: a 1.8 deg hybrid stepper behind a 20:1 gear.
inline constexpr int kMotorFullStepsPerTurn = 200;
inline constexpr int kMotorHalfStepsPerTurn = 400;
inline constexpr double kMotorFullStepDeg = 360.0 / kMotorFullStepsPerTurn;  // 1.8
inline constexpr double kTiltGearRatio = 20.0;
inline constexpr double kOutputShaftFullStepDeg = kMotorFullStepDeg / kTiltGearRatio;  // 0.09
inline constexpr double kOutputShaftHalfStepDeg = kOutputShaftFullStepDeg / 2.0;       // 0.045
static_assert(kMotorHalfStepsPerTurn == 2 * kMotorFullStepsPerTurn);

enum class StepMode : std::uint8_t { full_step, half_step };

// The value of each direction is the sign of the tilt change it causes.
enum class TiltDirection : std::int8_t { decreasing = -1, increasing = 1 };

constexpr int direction_sign(TiltDirection direction) { return static_cast<int>(direction); }

constexpr double output_shaft_deg_per_step(StepMode mode) {
  switch (mode) {
    case StepMode::full_step:
      return kOutputShaftFullStepDeg;
    case StepMode::half_step:
      return kOutputShaftHalfStepDeg;
  }
  return 0.0;
}

struct LptRegister {
  TiltDirection direction = TiltDirection::decreasing;
  bool clock_high = false;
  StepMode mode = StepMode::full_step;

  bool operator==(const LptRegister&) const = default;
};

constexpr LptRegister decode_lpt(std::uint8_t register_value) {
  return LptRegister{
      (register_value & kLptDirectionBit) != 0 ? TiltDirection::increasing
                                               : TiltDirection::decreasing,
      (register_value & kLptClockBit) != 0,
      (register_value & kLptModeBit) != 0 ? StepMode::half_step : StepMode::full_step,
  };
}

// The ignored bits are written as 0.
constexpr std::uint8_t encode_lpt(LptRegister lpt) {
  std::uint8_t value = 0;
  if (lpt.direction == TiltDirection::increasing) {
    value |= kLptDirectionBit;
  }
  if (lpt.clock_high) {
    value |= kLptClockBit;
  }
  if (lpt.mode == StepMode::half_step) {
    value |= kLptModeBit;
  }
  return value;
}

// One step of the motor, commanded by a rising clock edge.
struct StepPulse {
  base::SimTime at{};
  TiltDirection direction = TiltDirection::increasing;
  StepMode mode = StepMode::full_step;

  // Signed change of the tilt (output shaft) angle this step commands.
  constexpr double tilt_change_deg() const {
    return direction_sign(direction) * output_shaft_deg_per_step(mode);
  }
  bool operator==(const StepPulse&) const = default;
};

// Fed every register write with its arrival time; reports a step on each rising edge of
// DATA1, taking direction and mode from the same write (the board samples them at the edge).
class StepEdgeDetector {
 public:
  // `initial_register`: the register before the first write (0 after power-up).
  explicit StepEdgeDetector(std::uint8_t initial_register = 0);

  [[nodiscard]] std::optional<StepPulse> on_write(base::SimTime at, std::uint8_t register_value);

  LptRegister current() const { return decode_lpt(last_register_); }
  std::uint64_t steps_seen() const { return steps_seen_; }

 private:
  std::uint8_t last_register_;
  std::uint64_t steps_seen_ = 0;
};

}  // namespace ldoem::protocol
