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
#include "ldoem/protocol/sim_time.hpp"

namespace ldoem::plant {

using protocol::SimTime;

// The dynamic motor's state is sampled this often for the history; the ideal motor only
// changes at pulses, which are always recorded.
inline constexpr SimTime kTiltSamplePeriod = std::chrono::milliseconds(1);
// How far back tilt_at() can answer. A revolution lasts at most 200 ms (5 Hz, spec 6).
inline constexpr SimTime kTiltHistorySpan = std::chrono::seconds(2);

class TiltPlate {
 public:
  explicit TiltPlate(std::unique_ptr<motor::TiltMotor> motor);

  // One step pulse from the drive board, in time order.
  void on_step(const protocol::StepPulse& pulse);
  // Brings the motor to `now`, sampling the tilt on the way.
  void advance_to(SimTime now);
  // The tilt at `at` (not after the last advance_to): linear between samples, the oldest kept
  // sample before the history's start, the current tilt after its end.
  double tilt_at(SimTime at) const;
  double tilt_now() const { return motor_->tilt_rad(); }
  SimTime time() const { return time_; }
  const motor::TiltMotor& motor() const { return *motor_; }

 private:
  void record(SimTime at);

  std::unique_ptr<motor::TiltMotor> motor_;
  SimTime time_{0};
  std::deque<std::pair<SimTime, double>> samples_;
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
