#include <ldoem/motor/ideal_tilt_motor.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ldoem::motor {

double half_step_rad(const scene::TiltMotorConfig& config) {
  return config.step_angle_deg * std::numbers::pi / 180.0 / kHalfStepsPerFullStep / config.gear_ratio;
}

IdealTiltMotor::IdealTiltMotor(const scene::TiltMotorConfig& config)
    : half_step_rad_(half_step_rad(config)),
      // A tiny tolerance so that a stop at an exact multiple of the step (90 deg / 0.045 deg)
      // is reachable despite rounding of the division.
      min_half_steps_(static_cast<std::int64_t>(
          std::ceil(config.min_tilt_deg * std::numbers::pi / 180.0 / half_step_rad_ - 1e-9))),
      max_half_steps_(static_cast<std::int64_t>(
          std::floor(config.max_tilt_deg * std::numbers::pi / 180.0 / half_step_rad_ + 1e-9))) {}

void IdealTiltMotor::on_step_pulse(SimTime at, int direction, bool half_step) {
  advance_to(at);
  if (direction == 0) return;
  const std::int64_t delta = (direction > 0 ? 1 : -1) * (half_step ? 1 : kHalfStepsPerFullStep);
  commanded_half_steps_ += delta;
  note_tilt(now_, tilt_rad());  // where the plate was up to the pulse
  position_half_steps_ = std::clamp(position_half_steps_ + delta, min_half_steps_, max_half_steps_);
  note_tilt(now_, tilt_rad());
}

void IdealTiltMotor::advance_to(SimTime now) { now_ = std::max(now_, now); }

double IdealTiltMotor::tilt_rad() const { return static_cast<double>(position_half_steps_) * half_step_rad_; }

std::string IdealTiltMotor::dump() const {
  std::ostringstream text;
  text << "model: ideal\n"
       << "time_ns: " << now_.count() << "\n"
       << "commanded_half_steps: " << commanded_half_steps_ << "\n"
       << "position_half_steps: " << position_half_steps_ << "\n"
       << "tilt_rad: " << tilt_rad() << "\n"
       << "stops_half_steps: [" << min_half_steps_ << ", " << max_half_steps_ << "]\n";
  return text.str();
}

}  // namespace ldoem::motor
