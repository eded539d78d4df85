// The tilt stepper behind the drive board (D8): step pulses in, tilt angle out. Two models:
// IdealTiltMotor (exact steps) and DynamicTiltMotor (D9 motor_dynamics: ODE hinge, torque law,
// missed steps). Time is always a parameter (D7); no model reads a clock.
#pragma once

#include <ldoem/motor/tilt_history.hpp>
#include <ldoem/base/sim_time.hpp>
#include <ldoem/scene/scene.hpp>

#include <cstdint>
#include <memory>
#include <string>

namespace ldoem::motor {

using base::SimTime;

inline constexpr int kHalfStepsPerFullStep = 2;  // D8: full step = 200/turn, half step = 400/turn

class TiltMotor {
 public:
  virtual ~TiltMotor() = default;

  // One rising clock edge at `at` (D8 DATA1). direction: +1 = tilt grows (DATA0 = 1), -1 = falls;
  // anything else is taken by its sign and 0 is ignored. half_step: DATA2 (one half step rather
  // than one full step). Pulses must come in time order; one earlier than the model's time is
  // applied at the model's time.
  virtual void on_step_pulse(SimTime at, int direction, bool half_step) = 0;

  // Bring the physical state up to `now` (no-op for a time in the past).
  virtual void advance_to(SimTime now) = 0;

  // The physical tilt of the plate after the last advance_to / on_step_pulse (D5 sign: positive
  // raises the beam plane). This is what the sensor model uses, not the step counter.
  [[nodiscard]] virtual double tilt_rad() const = 0;

  // Every pulse received, counted in half steps (a full step counts 2), signed. Equals the
  // physical position only while no step was lost.
  [[nodiscard]] virtual std::int64_t commanded_steps() const = 0;

  // The state as text, one "key: value" per line, for test failures and --log-level debug.
  [[nodiscard]] virtual std::string dump() const = 0;

  // From now on the model records every change of the tilt into `history` (which must outlive
  // it; nullptr stops recording). See tilt_history.hpp for when each model records.
  void attach_history(TiltHistory* history) {
    history_ = history;
    note_tilt(SimTime::zero(), tilt_rad());
  }

 protected:
  void note_tilt(SimTime at, double tilt_rad) {
    if (history_ != nullptr) history_->record(at, tilt_rad);
  }

 private:
  TiltHistory* history_ = nullptr;
};

// Output-shaft angle of one half step: step_angle / 2 / gear ratio (D8: 0.045 deg by default).
[[nodiscard]] double half_step_rad(const scene::TiltMotorConfig& config);

// IdealTiltMotor unless the scene names motor_dynamics (D9).
[[nodiscard]] std::unique_ptr<TiltMotor> make_tilt_motor(const scene::Scene& scene);

}  // namespace ldoem::motor
