#include <ldoem/motor/dynamic_tilt_motor.hpp>

#include "model_units.hpp"
#include "ode_init.hpp"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ldoem::motor {
namespace {

// Pull-out: a two-phase hybrid stepper's torque-angle curve sin(pi/2 * lag / full step) turns
// over at a lag of 2 full steps; beyond it the rotor drops to the equilibrium one electrical
// cycle (4 full steps) behind.
constexpr std::int64_t kPullOutHalfSteps = 2 * kHalfStepsPerFullStep;
constexpr std::int64_t kElectricalCycleHalfSteps = 4 * kHalfStepsPerFullStep;
// The correction of the velocity law: braking deceleration as a share of what stall torque
// gives (margin for the speed-dependent torque), and the position gain near zero error per world
// step (< 1 keeps the discrete loop monotone).
constexpr double kBrakingShareOfStall = 0.5;
constexpr double kCorrectionPerWorldStep = 0.25;
// Feed-forward holds for this many pulse intervals after the last pulse, then ends.
constexpr double kFeedForwardHoldIntervals = 1.5;
// Pulses further apart than this are single moves, not a train: no feed-forward.
constexpr SimTime kLongestTrainInterval = std::chrono::milliseconds(100);
// Settled: below these the shaft is at rest on its field position and stepping is skipped.
constexpr double kSettledAngleRad = 1e-9;
constexpr double kSettledSpeedRadS = 1e-9;

}  // namespace

struct DynamicTiltMotor::Ode {
  dWorldID world = nullptr;
  dBodyID plate = nullptr;
  dJointID hinge = nullptr;
};

TiltDriveLimits tilt_drive_limits(const scene::TiltMotorConfig& config) {
  const double gear = config.gear_ratio;
  TiltDriveLimits limits{};
  limits.stall_torque_n_m = gear * config.torque_constant_n_m_per_a * config.supply_voltage_v /
                            config.winding_resistance_ohm;
  limits.no_load_speed_rad_s = config.supply_voltage_v / (gear * config.back_emf_v_s_per_rad);
  limits.total_inertia_kg_m2 = config.load_inertia_kg_m2 + gear * gear * config.rotor_inertia_kg_m2;
  limits.rated_speed_rad_s = 0.5 * limits.no_load_speed_rad_s;
  limits.rated_half_step_rate_hz = std::floor(limits.rated_speed_rad_s / half_step_rad(config));
  return limits;
}

int physics_substeps(double world_step_s) {
  if (!(world_step_s > kLongestPhysicsStep_s)) return 1;
  // The small tolerance keeps 1e-2 s at 10 sub-steps although 1e-2 / 1e-3 is 10.000000000000002.
  return static_cast<int>(std::ceil(world_step_s / kLongestPhysicsStep_s - 1e-9));
}

DynamicTiltMotor::DynamicTiltMotor(const scene::TiltMotorConfig& config)
    : config_(config),
      limits_(tilt_drive_limits(config)),
      half_step_rad_(half_step_rad(config)),
      substeps_(physics_substeps(config.world_step_s)),
      world_step_(std::chrono::duration_cast<SimTime>(
          std::chrono::duration<double>(config.world_step_s / physics_substeps(config.world_step_s)))),
      ode_(std::make_unique<Ode>()) {
  ensure_ode_initialised();
  ode_->world = dWorldCreate();
  dWorldSetGravity(ode_->world, 0, 0, 0);  // the worm gear is self-locking: gravity is not modelled
  ode_->plate = dBodyCreate(ode_->world);
  dMass mass;
  const double inertia = limits_.total_inertia_kg_m2;
  dMassSetParameters(&mass, 1.0, 0, 0, 0, inertia, inertia, inertia, 0, 0, 0);
  dBodySetMass(ode_->plate, &mass);
  ode_->hinge = dJointCreateHinge(ode_->world, nullptr);
  dJointAttach(ode_->hinge, ode_->plate, nullptr);
  dJointSetHingeAnchor(ode_->hinge, 0, 0, 0);
  // About -y so that a positive hinge angle is R_y(-phi) with phi > 0: the D5 sign of tilt.
  dJointSetHingeAxis(ode_->hinge, 0, -1, 0);
  const double degrees = std::numbers::pi / 180.0;
  dJointSetHingeParam(ode_->hinge, dParamLoStop, config.min_tilt_deg * degrees);
  dJointSetHingeParam(ode_->hinge, dParamHiStop, config.max_tilt_deg * degrees);
}

DynamicTiltMotor::~DynamicTiltMotor() {
  if (ode_ && ode_->world) dWorldDestroy(ode_->world);  // also destroys the body and the joint
}

double DynamicTiltMotor::tilt_rad() const { return dJointGetHingeAngle(ode_->hinge); }
double DynamicTiltMotor::speed_rad_s() const { return dJointGetHingeAngleRate(ode_->hinge); }
double DynamicTiltMotor::field_angle_rad() const {
  return static_cast<double>(commanded_half_steps_ - lost_half_steps_) * half_step_rad_;
}

void DynamicTiltMotor::on_step_pulse(SimTime at, int direction, bool half_step) {
  advance_to(at);
  if (direction == 0) return;
  note_tilt(std::max(at, world_time_), tilt_rad());  // a resting plate rested until this pulse
  const int sign = direction > 0 ? 1 : -1;
  const std::int64_t half_steps = half_step ? 1 : kHalfStepsPerFullStep;
  commanded_half_steps_ += sign * half_steps;

  const SimTime pulse_at = std::max(at, world_time_);
  const SimTime interval = pulse_at - last_pulse_at_;
  const bool same_train = last_pulse_at_.count() >= 0 && sign == last_pulse_direction_ &&
                          interval.count() > 0 && interval <= kLongestTrainInterval;
  if (same_train) {
    feed_forward_rad_s_ = sign * static_cast<double>(half_steps) * half_step_rad_ / detail::seconds(interval);
    feed_forward_until_ =
        pulse_at + std::chrono::duration_cast<SimTime>(interval * kFeedForwardHoldIntervals);
  } else {
    feed_forward_rad_s_ = 0.0;
  }
  last_pulse_at_ = pulse_at;
  last_pulse_direction_ = sign;
}

void DynamicTiltMotor::advance_to(SimTime now) {
  while (world_time_ + world_step_ <= now) {
    if (settled()) {
      // Nothing moves until the next pulse: jump in whole world steps so the grid stays fixed.
      world_time_ += ((now - world_time_) / world_step_) * world_step_;
      break;
    }
    step_world();
  }
}

bool DynamicTiltMotor::settled() const {
  return feed_forward_rad_s_ == 0.0 && std::abs(field_angle_rad() - tilt_rad()) < kSettledAngleRad &&
         std::abs(speed_rad_s()) < kSettledSpeedRadS;
}

void DynamicTiltMotor::lose_steps_past_pull_out() {
  const double pull_out_rad = static_cast<double>(kPullOutHalfSteps) * half_step_rad_;
  double lag_rad = field_angle_rad() - tilt_rad();
  while (std::abs(lag_rad) > pull_out_rad) {
    lost_half_steps_ += (lag_rad > 0 ? 1 : -1) * kElectricalCycleHalfSteps;
    lag_rad = field_angle_rad() - tilt_rad();
  }
}

void DynamicTiltMotor::step_world() {
  const double dt_s = detail::seconds(world_step_);
  if (feed_forward_rad_s_ != 0.0 && world_time_ > feed_forward_until_) feed_forward_rad_s_ = 0.0;
  lose_steps_past_pull_out();

  const double omega = speed_rad_s();
  const double error_rad = field_angle_rad() - tilt_rad();
  const double braking_rad_s2 = kBrakingShareOfStall * limits_.stall_torque_n_m / limits_.total_inertia_kg_m2;
  const double correction_rad_s = std::copysign(
      std::min(std::sqrt(2.0 * braking_rad_s2 * std::abs(error_rad)), kCorrectionPerWorldStep / dt_s * std::abs(error_rad)),
      error_rad);
  const double wanted_rad_s = feed_forward_rad_s_ + correction_rad_s;

  const double wanted_torque = limits_.total_inertia_kg_m2 * (wanted_rad_s - omega) / dt_s;
  const double sign = wanted_torque >= 0.0 ? 1.0 : -1.0;
  // D9 torque law with the supply applied in the direction wanted; the drive limits the current
  // to V / R, so braking (back-EMF adding to the supply) gets at most the stall torque.
  const double law_torque = config_.gear_ratio * config_.torque_constant_n_m_per_a *
                            (config_.supply_voltage_v - sign * config_.gear_ratio * config_.back_emf_v_s_per_rad * omega) /
                            config_.winding_resistance_ohm;
  const double available = std::clamp(law_torque, 0.0, limits_.stall_torque_n_m);
  dJointAddHingeTorque(ode_->hinge, sign * std::min(std::abs(wanted_torque), available));
  dWorldStep(ode_->world, dt_s);
  world_time_ += world_step_;
  ++world_steps_taken_;
  note_tilt(world_time_, tilt_rad());
}

std::string DynamicTiltMotor::dump() const {
  std::ostringstream text;
  text << "model: dynamic (ODE hinge)\n"
       << "time_ns: " << world_time_.count() << "\n"
       << "commanded_half_steps: " << commanded_half_steps_ << "\n"
       << "lost_half_steps: " << lost_half_steps_ << "\n"
       << "field_angle_rad: " << field_angle_rad() << "\n"
       << "tilt_rad: " << tilt_rad() << "\n"
       << "speed_rad_s: " << speed_rad_s() << "\n"
       << "feed_forward_rad_s: " << feed_forward_rad_s_ << "\n"
       << "world_steps_taken: " << world_steps_taken_ << "\n"
       << "physics_substeps: " << substeps_ << "\n"
       << "stall_torque_n_m: " << limits_.stall_torque_n_m << "\n"
       << "no_load_speed_rad_s: " << limits_.no_load_speed_rad_s << "\n"
       << "total_inertia_kg_m2: " << limits_.total_inertia_kg_m2 << "\n";
  return text.str();
}

}  // namespace ldoem::motor
