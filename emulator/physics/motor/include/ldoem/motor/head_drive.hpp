// The measuring head's own motor (the LD's spinning mirror), per D7 and D9 head_dynamics.
//
// The split:
//  - Spin-up is ALWAYS computed from HeadConfig (D7: TRANS_ROTATE answers when the simulated
//    speed is within 1 % of the target, after a spin-up from inertia and drive torque):
//      J d omega/dt = +-T_drive - b omega   (full drive torque towards the target, viscous b)
//    solved in closed form; once within reach the speed controller holds the target exactly.
//  - IdealHead (head_dynamics off): that curve and nothing else. The control unit places the
//    points of a revolution at their nominal angles.
//  - DynamicHead (head_dynamics on): the same curve plus a speed ripple of ripple_fraction at
//    ripple_frequency_hz while holding speed, so each point's angle (angle_rad at its own time)
//    departs slightly from the nominal grid.
// Times before the last set_target are answered as at that time.
#pragma once

#include <ldoem/base/sim_time.hpp>
#include <ldoem/scene/scene.hpp>

#include <memory>
#include <optional>
#include <string>

namespace ldoem::motor {

using base::SimTime;

inline constexpr double kSpeedReachedTolerance = 0.01;  // D7: within 1 % of the target

// One spin-up or spin-down: the closed-form solution from a starting speed and angle towards a
// target, then constant at the target (or asymptotically below it when friction forbids it).
class SpinUpCurve {
 public:
  SpinUpCurve() = default;
  SpinUpCurve(const scene::HeadConfig& config, SimTime start, double start_speed_rad_s, double start_angle_rad,
              double target_speed_rad_s);

  [[nodiscard]] double speed_rad_s(SimTime at) const;
  [[nodiscard]] double angle_rad(SimTime at) const;
  // When the target is held (speed exactly at target), or nothing if friction forbids it.
  [[nodiscard]] std::optional<SimTime> holds_target_from() const;
  // First time the speed is within the relative tolerance of `speed_rad_s`, or nothing.
  [[nodiscard]] std::optional<SimTime> first_within(double speed_rad_s, double tolerance) const;
  [[nodiscard]] double target_speed_rad_s() const { return target_rad_s_; }
  [[nodiscard]] SimTime start() const { return start_; }

 private:
  // Speed and angle after tau seconds of driving (before clamping to the target).
  [[nodiscard]] double driven_speed(double tau_s) const;
  [[nodiscard]] double driven_angle(double tau_s) const;
  // Seconds of driving to reach `speed`, or nothing if the curve never gets there.
  [[nodiscard]] std::optional<double> time_to_speed(double speed_rad_s) const;

  SimTime start_{0};
  double start_speed_rad_s_ = 0.0;
  double start_angle_rad_ = 0.0;
  double target_rad_s_ = 0.0;
  double acceleration_rad_s2_ = 0.0;   // T_drive / J, signed towards the target
  double friction_rate_per_s_ = 0.0;   // b / J
  std::optional<double> reach_s_;      // driving time until the target is held
};

class HeadDrive {
 public:
  virtual ~HeadDrive() = default;
  // New target speed from `now` on (0 stops the head).
  virtual void set_target(SimTime now, double hz) = 0;
  [[nodiscard]] virtual double speed_hz(SimTime at) const = 0;
  // Integrated head angle (unbounded; callers wrap it), continuous across set_target calls.
  [[nodiscard]] virtual double angle_rad(SimTime at) const = 0;
  // D7: the time the speed comes within 1 % of `hz` on the current curve (TRANS_ROTATE answers
  // then); nothing if it never does (hz is not where the head is going, or friction forbids it).
  [[nodiscard]] virtual std::optional<SimTime> reached_at(double hz) const = 0;
  [[nodiscard]] virtual std::string dump() const = 0;
};

class IdealHead final : public HeadDrive {
 public:
  explicit IdealHead(const scene::HeadConfig& config) : config_(config) {}
  void set_target(SimTime now, double hz) override;
  [[nodiscard]] double speed_hz(SimTime at) const override;
  [[nodiscard]] double angle_rad(SimTime at) const override;
  [[nodiscard]] std::optional<SimTime> reached_at(double hz) const override;
  [[nodiscard]] std::string dump() const override;

 private:
  scene::HeadConfig config_;
  SpinUpCurve curve_;
};

class DynamicHead final : public HeadDrive {
 public:
  explicit DynamicHead(const scene::HeadConfig& config) : config_(config) {}
  void set_target(SimTime now, double hz) override;
  [[nodiscard]] double speed_hz(SimTime at) const override;
  [[nodiscard]] double angle_rad(SimTime at) const override;
  [[nodiscard]] std::optional<SimTime> reached_at(double hz) const override;
  [[nodiscard]] std::string dump() const override;

 private:
  // Ripple's speed and angle contributions at `at` (zero until the target is held).
  [[nodiscard]] double ripple_speed_rad_s(SimTime at) const;
  [[nodiscard]] double ripple_angle_rad(SimTime at) const;

  scene::HeadConfig config_;
  SpinUpCurve curve_;
  double ripple_angle_carry_rad_ = 0.0;  // ripple angle accumulated before the last set_target
};

// IdealHead unless the scene names head_dynamics (D9).
[[nodiscard]] std::unique_ptr<HeadDrive> make_head_drive(const scene::Scene& scene);

}  // namespace ldoem::motor
