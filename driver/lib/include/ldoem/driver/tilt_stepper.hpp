// The tilt stepper as the host drives it (D8): clock pulses on an LptPort, direction and mode
// set before each rising edge, paced by an injected Sleeper so that tests see exact sequences.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

#include "ldoem/driver/error.hpp"
#include "ldoem/driver/lpt_port.hpp"
#include "ldoem/protocol/lpt.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::driver {

using protocol::StepMode;
using protocol::TiltDirection;

// Where pulse timing comes from. Times are on one monotonic time line (SimTime = ns).
class Sleeper {
 public:
  virtual ~Sleeper() = default;
  virtual base::SimTime now() = 0;
  // Returns at or after `time` (immediately when it has passed), or early once interrupted.
  virtual void sleep_until(base::SimTime time) = 0;
  // Thread-safe: wakes a sleep in progress and makes every later one return at once.
  virtual void interrupt() {}
  virtual bool interrupted() const { return false; }
};

// The real one: absolute deadlines on CLOCK_MONOTONIC, so pulses do not drift with the time
// the writes take, waited for on a condition variable so that interrupt() ends a long move.
class MonotonicSleeper final : public Sleeper {
 public:
  base::SimTime now() override;
  void sleep_until(base::SimTime time) override;
  void interrupt() override;
  bool interrupted() const override;

 private:
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool interrupted_ = false;
};

// The longest step period a move accepts (a lower rate would overflow the nanosecond clock long
// before it made sense for a tilt plate).
inline constexpr std::chrono::seconds kMaxStepPeriod{3600};

// Half-steps per full step: the position is kept in the finer unit (D8).
inline constexpr std::int64_t kHalfStepsPerFullStep = 2;

class TiltStepper {
 public:
  // Neither reference is owned; both must outlive the stepper. The position starts at 0
  // (level, D5) and the register is assumed 0 until the first write.
  TiltStepper(LptPort& port, Sleeper& sleeper);

  // `steps` pulses at `step_rate_hz` in `direction` and `mode`. Per step period T, starting
  // at t0 = now: at t0 the register takes DIR/MODE with CLK low (written only when it
  // changes), then for step k CLK rises at t0 + (k + 1/2) T (the step, D8) and falls at
  // t0 + (k + 1) T. The move therefore takes steps * T and leaves CLK low.
  // invalid_argument for a rate that is not finite, not > 0 or so low that one step would take
  // longer than kMaxStepPeriod; a failing write stops the move with the position counting the
  // steps whose rising edge was written. An interrupted sleeper stops it the same way
  // (ErrorKind::interrupted), leaving CLK low.
  Status move(std::uint32_t steps, TiltDirection direction, StepMode mode, double step_rate_hz);

  // Moves to the nearest position of `mode`'s step size to `target_deg` (may be 0 steps).
  Status move_to_angle(double target_deg, StepMode mode, double step_rate_hz);

  // Commanded position in half-steps (positive = tilt angle grew) and as an angle:
  // half-steps * 0.045 deg (D8: 1.8 deg / 20:1, halved).
  std::int64_t position_half_steps() const { return position_half_steps_; }
  double tilt_angle_deg() const;
  // Declare the current position to be `half_steps` (after homing, for instance).
  void set_position_half_steps(std::int64_t half_steps) { position_half_steps_ = half_steps; }

 private:
  Status write(std::uint8_t value);

  LptPort& port_;
  Sleeper& sleeper_;
  std::int64_t position_half_steps_ = 0;
  std::optional<std::uint8_t> last_written_;
};

// Half-steps one step of `mode` moves (1 or 2).
constexpr std::int64_t half_steps_per_step(StepMode mode) {
  return mode == StepMode::half_step ? 1 : kHalfStepsPerFullStep;
}

}  // namespace ldoem::driver
