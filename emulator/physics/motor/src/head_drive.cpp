#include <ldoem/motor/head_drive.hpp>

#include "model_units.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ldoem::motor {
namespace {

SimTime after(SimTime start, double seconds_later) {
  return start + std::chrono::ceil<SimTime>(std::chrono::duration<double>(seconds_later));
}

}  // namespace

SpinUpCurve::SpinUpCurve(const scene::HeadConfig& config, SimTime start, double start_speed_rad_s,
                         double start_angle_rad, double target_speed_rad_s)
    : start_(start),
      start_speed_rad_s_(start_speed_rad_s),
      start_angle_rad_(start_angle_rad),
      target_rad_s_(target_speed_rad_s) {
  const double towards = target_speed_rad_s > start_speed_rad_s ? 1.0
                         : target_speed_rad_s < start_speed_rad_s ? -1.0
                                                                  : 0.0;
  if (config.inertia_kg_m2 > 0.0) {
    acceleration_rad_s2_ = towards * config.drive_torque_n_m / config.inertia_kg_m2;
    friction_rate_per_s_ = std::max(0.0, config.friction_n_m_s) / config.inertia_kg_m2;
  }
  reach_s_ = towards == 0.0 ? std::optional<double>(0.0) : time_to_speed(target_speed_rad_s);
}

double SpinUpCurve::driven_speed(double tau_s) const {
  if (friction_rate_per_s_ == 0.0) return start_speed_rad_s_ + acceleration_rad_s2_ * tau_s;
  const double terminal = acceleration_rad_s2_ / friction_rate_per_s_;  // where drive = friction
  return terminal + (start_speed_rad_s_ - terminal) * std::exp(-friction_rate_per_s_ * tau_s);
}

double SpinUpCurve::driven_angle(double tau_s) const {
  if (friction_rate_per_s_ == 0.0) {
    return start_speed_rad_s_ * tau_s + 0.5 * acceleration_rad_s2_ * tau_s * tau_s;
  }
  const double terminal = acceleration_rad_s2_ / friction_rate_per_s_;
  return terminal * tau_s +
         (start_speed_rad_s_ - terminal) * (1.0 - std::exp(-friction_rate_per_s_ * tau_s)) / friction_rate_per_s_;
}

std::optional<double> SpinUpCurve::time_to_speed(double speed_rad_s) const {
  if (speed_rad_s == start_speed_rad_s_) return 0.0;
  if (friction_rate_per_s_ == 0.0) {
    if (acceleration_rad_s2_ == 0.0) return std::nullopt;
    const double tau_s = (speed_rad_s - start_speed_rad_s_) / acceleration_rad_s2_;
    return tau_s >= 0.0 ? std::optional<double>(tau_s) : std::nullopt;
  }
  const double terminal = acceleration_rad_s2_ / friction_rate_per_s_;
  const double remaining_share = (speed_rad_s - terminal) / (start_speed_rad_s_ - terminal);
  if (!(remaining_share > 0.0 && remaining_share <= 1.0)) return std::nullopt;  // never, or behind us
  return -std::log(remaining_share) / friction_rate_per_s_;
}

double SpinUpCurve::speed_rad_s(SimTime at) const {
  const double tau_s = std::max(0.0, detail::seconds(at - start_));
  if (reach_s_ && tau_s >= *reach_s_) return target_rad_s_;
  return driven_speed(tau_s);
}

double SpinUpCurve::angle_rad(SimTime at) const {
  const double tau_s = std::max(0.0, detail::seconds(at - start_));
  if (reach_s_ && tau_s >= *reach_s_) {
    return start_angle_rad_ + driven_angle(*reach_s_) + target_rad_s_ * (tau_s - *reach_s_);
  }
  return start_angle_rad_ + driven_angle(tau_s);
}

std::optional<SimTime> SpinUpCurve::holds_target_from() const {
  if (!reach_s_) return std::nullopt;
  return after(start_, *reach_s_);
}

std::optional<SimTime> SpinUpCurve::first_within(double speed_rad_s, double tolerance) const {
  const double low = std::abs(speed_rad_s) * (1.0 - tolerance);
  const double high = std::abs(speed_rad_s) * (1.0 + tolerance);
  if (start_speed_rad_s_ >= low && start_speed_rad_s_ <= high) return start_;
  const double edge = start_speed_rad_s_ < low ? low : high;
  const std::optional<double> tau_s = time_to_speed(edge);
  // Past the hold time the speed is the target; if the band lies beyond it, it is never reached.
  if (!tau_s || (reach_s_ && *tau_s > *reach_s_)) {
    if (reach_s_ && target_rad_s_ >= low && target_rad_s_ <= high) return after(start_, *reach_s_);
    return std::nullopt;
  }
  return after(start_, *tau_s);
}

void IdealHead::set_target(SimTime now, double hz) {
  curve_ = SpinUpCurve(config_, now, curve_.speed_rad_s(now), curve_.angle_rad(now),
                       detail::kRadiansPerTurn * std::max(0.0, hz));
}
double IdealHead::speed_hz(SimTime at) const { return curve_.speed_rad_s(at) / detail::kRadiansPerTurn; }
double IdealHead::angle_rad(SimTime at) const { return curve_.angle_rad(at); }
std::optional<SimTime> IdealHead::reached_at(double hz) const {
  return curve_.first_within(detail::kRadiansPerTurn * hz, kSpeedReachedTolerance);
}
std::string IdealHead::dump() const {
  std::ostringstream text;
  text << "model: ideal head\n"
       << "curve_start_ns: " << curve_.start().count() << "\n"
       << "target_hz: " << curve_.target_speed_rad_s() / detail::kRadiansPerTurn << "\n";
  return text.str();
}

double DynamicHead::ripple_speed_rad_s(SimTime at) const {
  const std::optional<SimTime> held = curve_.holds_target_from();
  if (!held || at < *held || config_.ripple_frequency_hz <= 0.0) return 0.0;
  const double phase = detail::kRadiansPerTurn * config_.ripple_frequency_hz * detail::seconds(at - *held);
  return curve_.target_speed_rad_s() * config_.ripple_fraction * std::sin(phase);
}

double DynamicHead::ripple_angle_rad(SimTime at) const {
  const std::optional<SimTime> held = curve_.holds_target_from();
  if (!held || at < *held || config_.ripple_frequency_hz <= 0.0) return 0.0;
  const double angular_frequency = detail::kRadiansPerTurn * config_.ripple_frequency_hz;
  const double phase = angular_frequency * detail::seconds(at - *held);
  return curve_.target_speed_rad_s() * config_.ripple_fraction * (1.0 - std::cos(phase)) / angular_frequency;
}

void DynamicHead::set_target(SimTime now, double hz) {
  ripple_angle_carry_rad_ += ripple_angle_rad(now);
  curve_ = SpinUpCurve(config_, now, curve_.speed_rad_s(now), curve_.angle_rad(now),
                       detail::kRadiansPerTurn * std::max(0.0, hz));
}
double DynamicHead::speed_hz(SimTime at) const {
  return (curve_.speed_rad_s(at) + ripple_speed_rad_s(at)) / detail::kRadiansPerTurn;
}
double DynamicHead::angle_rad(SimTime at) const {
  return curve_.angle_rad(at) + ripple_angle_carry_rad_ + ripple_angle_rad(at);
}
std::optional<SimTime> DynamicHead::reached_at(double hz) const {
  return curve_.first_within(detail::kRadiansPerTurn * hz, kSpeedReachedTolerance);
}
std::string DynamicHead::dump() const {
  std::ostringstream text;
  text << "model: dynamic head (ripple " << config_.ripple_fraction << " at " << config_.ripple_frequency_hz
       << " Hz)\n"
       << "curve_start_ns: " << curve_.start().count() << "\n"
       << "target_hz: " << curve_.target_speed_rad_s() / detail::kRadiansPerTurn << "\n"
       << "ripple_angle_carry_rad: " << ripple_angle_carry_rad_ << "\n";
  return text.str();
}

std::unique_ptr<HeadDrive> make_head_drive(const scene::Scene& scene) {
  if (scene.effects.has(scene::Effect::head_dynamics)) return std::make_unique<DynamicHead>(scene.scanner.head);
  return std::make_unique<IdealHead>(scene.scanner.head);
}

}  // namespace ldoem::motor
