#include "ldoem/driver/tilt_stepper.hpp"

#include <time.h>

#include <cerrno>
#include <chrono>
#include <cmath>

namespace ldoem::driver {

using base::SimTime;

SimTime MonotonicSleeper::now() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
}

void MonotonicSleeper::sleep_until(SimTime time) {
  // steady_clock is CLOCK_MONOTONIC on Linux; the wait is on an absolute deadline, so spurious
  // wake-ups simply wait again for the same instant.
  const std::chrono::steady_clock::time_point deadline{std::chrono::duration_cast<std::chrono::steady_clock::duration>(time)};
  std::unique_lock lock(mutex_);
  wake_.wait_until(lock, deadline, [this] { return interrupted_; });
}

void MonotonicSleeper::interrupt() {
  {
    std::lock_guard lock(mutex_);
    interrupted_ = true;
  }
  wake_.notify_all();
}

bool MonotonicSleeper::interrupted() const {
  std::lock_guard lock(mutex_);
  return interrupted_;
}

TiltStepper::TiltStepper(LptPort& port, Sleeper& sleeper) : port_(port), sleeper_(sleeper) {}

Status TiltStepper::write(std::uint8_t value) {
  auto written = port_.write_data(value);
  if (written) {
    last_written_ = value;
  }
  return written;
}

Status TiltStepper::move(std::uint32_t steps, TiltDirection direction, StepMode mode, double step_rate_hz) {
  const double longest_period_s = std::chrono::duration<double>(kMaxStepPeriod).count();
  if (!std::isfinite(step_rate_hz) || !(step_rate_hz * longest_period_s >= 1.0)) {
    return fail(make_error(ErrorKind::invalid_argument, "move", port_.name(),
                           "step rate must be a finite number of at least one step per " +
                               std::to_string(kMaxStepPeriod.count()) + " s"));
  }
  const SimTime period = std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(1.0 / step_rate_hz));
  const SimTime half_period = period / 2;
  const protocol::LptRegister low{direction, false, mode};
  const protocol::LptRegister high{direction, true, mode};
  const std::uint8_t setup = protocol::encode_lpt(low);
  const SimTime start = sleeper_.now();
  if (last_written_ != setup) {
    auto written = write(setup);
    if (!written) {
      return written;
    }
  }
  const std::int64_t half_steps = protocol::direction_sign(direction) * half_steps_per_step(mode);
  for (std::uint32_t k = 0; k < steps; ++k) {
    const SimTime step_start = start + period * static_cast<std::int64_t>(k);
    sleeper_.sleep_until(step_start + half_period);
    if (sleeper_.interrupted()) {
      return fail(make_error(ErrorKind::interrupted, "move", port_.name(),
                             "cancelled after " + std::to_string(k) + " of " + std::to_string(steps) + " steps"));
    }
    auto rising = write(protocol::encode_lpt(high));
    if (!rising) {
      return rising;
    }
    position_half_steps_ += half_steps;  // D8: the rising edge is the step
    sleeper_.sleep_until(step_start + period);
    auto falling = write(setup);
    if (!falling) {
      return falling;
    }
  }
  return ok();
}

Status TiltStepper::move_to_angle(double target_deg, StepMode mode, double step_rate_hz) {
  if (!std::isfinite(target_deg)) {
    return fail(make_error(ErrorKind::invalid_argument, "move", port_.name(), "target angle is not finite"));
  }
  const double step_deg = protocol::output_shaft_deg_per_step(mode);
  const double delta_steps = std::round((target_deg - tilt_angle_deg()) / step_deg);
  if (std::fabs(delta_steps) > static_cast<double>(UINT32_MAX)) {
    return fail(make_error(ErrorKind::invalid_argument, "move", port_.name(), "target angle out of reach"));
  }
  const auto steps = static_cast<std::uint32_t>(std::fabs(delta_steps));
  const TiltDirection direction = delta_steps >= 0.0 ? TiltDirection::increasing : TiltDirection::decreasing;
  return move(steps, direction, mode, step_rate_hz);
}

double TiltStepper::tilt_angle_deg() const {
  return static_cast<double>(position_half_steps_) * protocol::kOutputShaftHalfStepDeg;
}

}  // namespace ldoem::driver
