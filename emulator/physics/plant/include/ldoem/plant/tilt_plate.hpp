// The tilt plate and its stepper (D8, D9): register writes (pty bytes or gpio edges)
// -> StepEdgeDetector -> TiltMotor, plus a short history of the plate's tilt so that the sensor
// model can ask for the tilt at a beam's own time after the fact (sweep_motion), or at the start
// of a revolution (otherwise). The control unit measures a revolution only once its last point
// has passed, so every question is about the past, and the history answers it.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <utility>

#include "ldoem/motor/tilt_motor.hpp"
#include "ldoem/protocol/lpt.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::plant {

using base::SimTime;

// How far back tilt_at() can answer. A revolution lasts at most 200 ms (5 Hz, spec 6).
inline constexpr SimTime kTiltHistorySpan = motor::TiltHistory::kDefaultSpan;

class TiltPlate {
 public:
  explicit TiltPlate(std::unique_ptr<motor::TiltMotor> motor);
  // The motor keeps a pointer to history_: the plate stays where it was built.
  TiltPlate(const TiltPlate&) = delete;
  TiltPlate& operator=(const TiltPlate&) = delete;

  // One step pulse from the drive board, in time order.
  void on_step(const protocol::StepPulse& pulse);
  // Brings the motor to `now` in one call: the motor records its own tilt changes into the
  // history (motor/tilt_history.hpp), so an idle plate or an ideal motor costs nothing per step.
  void advance_to(SimTime now);
  // The tilt at `at` (not after the last advance_to): linear between records, the oldest kept
  // record before the history's start, the current tilt after its end.
  double tilt_at(SimTime at) const { return history_.tilt_at(at, motor_->tilt_rad()); }
  std::size_t history_size() const { return history_.size(); }
  double tilt_now() const { return motor_->tilt_rad(); }
  SimTime time() const { return time_; }
  const motor::TiltMotor& motor() const { return *motor_; }

 private:
  motor::TiltHistory history_{kTiltHistorySpan};  // before motor_: the motor writes into it
  std::unique_ptr<motor::TiltMotor> motor_;
  SimTime time_{0};
};

// The drive board of D8: the data register's writes in, step pulses to the tilt plate out.
class StepperDriveBoard {
 public:
  explicit StepperDriveBoard(TiltPlate& plate, std::uint8_t initial_register = 0)
      : plate_(plate), detector_(initial_register), register_(initial_register) {}

  // pty back end: every byte is a new register value, stamped with its arrival time (D8).
  void on_register_write(SimTime at, std::uint8_t register_value);
  // gpio back end: line `bit` (DIR, CLK, MODE = DATA0..2) changed to `level` at `at`.
  void on_line_change(SimTime at, std::uint8_t bit, bool level);

  std::uint64_t steps_seen() const { return detector_.steps_seen(); }
  std::uint8_t register_value() const { return register_; }

 private:
  TiltPlate& plate_;
  protocol::StepEdgeDetector detector_;
  std::uint8_t register_;
};

}  // namespace ldoem::plant
