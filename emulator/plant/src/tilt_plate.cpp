#include "ldoem/plant/tilt_plate.hpp"

#include <algorithm>

namespace ldoem::plant {

TiltPlate::TiltPlate(std::unique_ptr<motor::TiltMotor> motor) : motor_(std::move(motor)) { record(time_); }

void TiltPlate::on_step(const protocol::StepPulse& pulse) {
  const SimTime at = std::max(pulse.at, time_);
  advance_to(at);
  motor_->on_step_pulse(at, protocol::direction_sign(pulse.direction),
                        pulse.mode == protocol::StepMode::half_step);
  record(at);
}

void TiltPlate::advance_to(SimTime now) {
  while (time_ < now) {
    const SimTime next = std::min(now, time_ + kTiltSamplePeriod);
    motor_->advance_to(next);
    time_ = next;
    record(next);
  }
}

void TiltPlate::record(SimTime at) {
  const double tilt = motor_->tilt_rad();
  // Steady stretches keep only their two ends, so an idle plate costs no memory.
  if (samples_.size() >= 2 && samples_.back().second == tilt && samples_[samples_.size() - 2].second == tilt) {
    samples_.back().first = at;
  } else {
    samples_.emplace_back(at, tilt);
  }
  while (samples_.size() > 2 && samples_[1].first < at - kTiltHistorySpan) {
    samples_.pop_front();
  }
}

double TiltPlate::tilt_at(SimTime at) const {
  if (samples_.empty() || at >= samples_.back().first) {
    return motor_->tilt_rad();
  }
  if (at <= samples_.front().first) {
    return samples_.front().second;
  }
  // The last sample at or before `at`: a pulse records two samples at one time, and the later
  // one (after the step) holds from then on.
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), at,
                                      [](SimTime t, const auto& sample) { return t < sample.first; });
  const auto before = std::prev(after);
  const double span_ns = static_cast<double>((after->first - before->first).count());
  if (span_ns <= 0.0) {
    return before->second;
  }
  const double fraction = static_cast<double>((at - before->first).count()) / span_ns;
  return before->second + fraction * (after->second - before->second);
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
