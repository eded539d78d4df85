// Exact steps: every pulse moves the plate by exactly one full (0.09 deg) or half (0.045 deg)
// step at the output shaft (D8), at the instant of the pulse. The plate's hard stops
// (TiltMotorConfig::min/max_tilt_deg) are the only way to lose a step: a pulse that would drive
// the plate through a stop is counted but does not move it.
#pragma once

#include <ldoem/motor/tilt_motor.hpp>

namespace ldoem::motor {

class IdealTiltMotor final : public TiltMotor {
 public:
  explicit IdealTiltMotor(const scene::TiltMotorConfig& config);

  void on_step_pulse(SimTime at, int direction, bool half_step) override;
  void advance_to(SimTime now) override;
  [[nodiscard]] double tilt_rad() const override;
  [[nodiscard]] std::int64_t commanded_steps() const override { return commanded_half_steps_; }
  [[nodiscard]] std::string dump() const override;

  [[nodiscard]] std::int64_t position_half_steps() const { return position_half_steps_; }

 private:
  double half_step_rad_;
  std::int64_t min_half_steps_;
  std::int64_t max_half_steps_;
  std::int64_t commanded_half_steps_ = 0;
  std::int64_t position_half_steps_ = 0;
  SimTime now_{0};
};

}  // namespace ldoem::motor
