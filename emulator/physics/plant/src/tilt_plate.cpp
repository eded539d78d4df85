#include "ldoem/plant/tilt_plate.hpp"

#include <algorithm>

namespace ldoem::plant {

TiltPlate::TiltPlate(std::unique_ptr<motor::TiltMotor> motor) : motor_(std::move(motor)) {
  motor_->attach_history(&history_);
}

void TiltPlate::on_step(const protocol::StepPulse& pulse) {
  const SimTime at = std::max(pulse.at, time_);
  advance_to(at);
  motor_->on_step_pulse(at, protocol::direction_sign(pulse.direction),
                        pulse.mode == protocol::StepMode::half_step);
}

void TiltPlate::advance_to(SimTime now) {
  if (now <= time_) return;
  motor_->advance_to(now);
  time_ = now;
}

void StepperDriveBoard::on_register_write(SimTime at, std::uint8_t register_value) {
  register_ = register_value;
  if (const auto pulse = detector_.on_write(at, register_value)) {
    plate_.on_step(*pulse);
  }
}

void StepperDriveBoard::on_line_change(SimTime at, std::uint8_t bit, bool level) {
  const auto value = static_cast<std::uint8_t>(level ? (register_ | bit) : (register_ & ~bit));
  on_register_write(at, value);
}

}  // namespace ldoem::plant
