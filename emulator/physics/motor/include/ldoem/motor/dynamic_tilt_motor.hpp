// D9 motor_dynamics: the plate on an ODE hinge about the tilt axis, driven through the gear by
//   T = G k_t (V - G k_v omega) / R        (output shaft; omega the output speed)
// The drive aims the shaft at the field position (the steps received minus the steps lost) with
// a velocity law: the pulse rate as feed-forward plus a correction that never asks for more speed
// than can be braked within the remaining distance (v = sqrt(2 a_brake |e|), linear near 0).
// The torque the law allows caps what it gets. When pulses outrun that torque the rotor lags the
// field; past the pull-out lag (2 full steps, where a two-phase stepper's torque-angle curve
// turns over) the detent is lost and the rotor falls back by one electrical cycle (4 full steps):
// those steps are lost, the step counter and the physical angle diverge, and tilt_rad() reports
// the physical angle.
//
// The world is stepped at TiltMotorConfig::world_step_s; once the shaft has settled and no pulse
// is pending, advance_to() stops stepping (no cost and no drift while idle). A world step longer
// than kLongestPhysicsStep_s is split into equal sub-steps no longer than that, and the model
// runs (and takes pulses) on the sub-step grid: at 1e-2 s five 500 Hz pulses would pile up
// between two steps, the field would jump past the pull-out lag and the model would lose steps
// a real drive does not (the 24.7 deg RMS tilt error the accuracy report once showed).
#pragma once

#include <ldoem/motor/tilt_motor.hpp>

#include <memory>

namespace ldoem::motor {

// Derived constants of the torque law, at the output shaft.
struct TiltDriveLimits {
  double stall_torque_n_m;      // G k_t V / R: also the drive's current limit
  double no_load_speed_rad_s;   // V / (G k_v)
  double total_inertia_kg_m2;   // load + G^2 rotor
  double rated_speed_rad_s;     // no-load / 2: the torque law still leaves half the stall torque
  double rated_half_step_rate_hz;  // rated speed in half steps per second (floor)
};
[[nodiscard]] TiltDriveLimits tilt_drive_limits(const scene::TiltMotorConfig& config);

// The longest step the hinge and the drive law are integrated with.
inline constexpr double kLongestPhysicsStep_s = 1.0e-3;

// How many equal physics sub-steps one world step of `world_step_s` is split into (>= 1).
[[nodiscard]] int physics_substeps(double world_step_s);

class DynamicTiltMotor final : public TiltMotor {
 public:
  explicit DynamicTiltMotor(const scene::TiltMotorConfig& config);
  ~DynamicTiltMotor() override;
  DynamicTiltMotor(const DynamicTiltMotor&) = delete;
  DynamicTiltMotor& operator=(const DynamicTiltMotor&) = delete;

  void on_step_pulse(SimTime at, int direction, bool half_step) override;
  void advance_to(SimTime now) override;
  [[nodiscard]] double tilt_rad() const override;
  [[nodiscard]] std::int64_t commanded_steps() const override { return commanded_half_steps_; }
  [[nodiscard]] std::string dump() const override;

  [[nodiscard]] std::int64_t lost_half_steps() const { return lost_half_steps_; }
  [[nodiscard]] double speed_rad_s() const;
  // Sub-steps integrated so far (world steps when world_step_s <= kLongestPhysicsStep_s).
  [[nodiscard]] std::uint64_t world_steps_taken() const { return world_steps_taken_; }
  [[nodiscard]] int substeps_per_world_step() const { return substeps_; }

 private:
  struct Ode;  // ODE handles, kept out of this header
  void step_world();
  [[nodiscard]] bool settled() const;
  void lose_steps_past_pull_out();
  [[nodiscard]] double field_angle_rad() const;

  scene::TiltMotorConfig config_;
  TiltDriveLimits limits_;
  double half_step_rad_;
  int substeps_;
  SimTime world_step_;  // the sub-step actually integrated: world_step_s / substeps_
  std::unique_ptr<Ode> ode_;
  SimTime world_time_{0};
  std::int64_t commanded_half_steps_ = 0;
  std::int64_t lost_half_steps_ = 0;
  // Feed-forward from the pulse train: the last pulse's time and direction, and the rate implied
  // by the interval to the one before (0 when unknown or expired).
  SimTime last_pulse_at_{-1};
  int last_pulse_direction_ = 0;
  double feed_forward_rad_s_ = 0.0;
  SimTime feed_forward_until_{0};
  std::uint64_t world_steps_taken_ = 0;
};

}  // namespace ldoem::motor
