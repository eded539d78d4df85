// What the tilt motor tests share: the default drive, its step sizes, and trains of step pulses.
#pragma once

#include <ldoem/motor/tilt_motor.hpp>

#include <chrono>
#include <cstdint>
#include <numbers>

namespace ldoem::motor::test {

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline const scene::TiltMotorConfig kConfig{};
inline const double kHalfStep = half_step_rad(kConfig);
inline const double kFullStep = 2 * kHalfStep;

// Sends `count` full steps (or half steps) in `direction` at `rate_hz` starting at `start`;
// returns the time after the last pulse.
inline SimTime pulse_train(TiltMotor& motor, SimTime start, std::int64_t count, int direction, double rate_hz,
                           bool half_step = false) {
  const auto interval = std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(1.0 / rate_hz));
  SimTime at = start;
  for (std::int64_t i = 0; i < count; ++i) {
    motor.on_step_pulse(at, direction, half_step);
    at += interval;
  }
  return at;
}

}  // namespace ldoem::motor::test
