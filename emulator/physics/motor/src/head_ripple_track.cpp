#include <ldoem/motor/head_ripple_track.hpp>

#include "model_units.hpp"

#include <cmath>
#include <optional>

namespace ldoem::motor {
namespace {

// Newton's method on the head angle: the ripple bends the angle by at most a few parts in 10^3
// of a revolution, so three iterations land far below a nanosecond.
constexpr int kNewtonIterations = 4;
// Below this speed the head is taken to stand still: no point fires, no shift is defined.
constexpr double kStandingStillHz = 1e-6;


// Seconds after `start` at which `head` has turned `angle_rad` past its angle at `start`.
std::optional<double> seconds_to_turn(const HeadDrive& head, SimTime start, double angle_rad) {
  const double start_angle_rad = head.angle_rad(start);
  const double start_hz = head.speed_hz(start);
  if (!(start_hz > kStandingStillHz)) return std::nullopt;
  double tau_s = angle_rad / (detail::kRadiansPerTurn * start_hz);
  for (int i = 0; i < kNewtonIterations; ++i) {
    const SimTime at = start + std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(tau_s));
    const double hz = head.speed_hz(at);
    if (!(hz > kStandingStillHz)) return std::nullopt;
    const double error_rad = head.angle_rad(at) - start_angle_rad - angle_rad;
    tau_s -= error_rad / (detail::kRadiansPerTurn * hz);
  }
  return tau_s;
}

}  // namespace

void HeadRippleTrack::set_target(SimTime now, double hz) {
  rippling_.set_target(now, hz);
  ideal_.set_target(now, hz);
}

SimTime HeadRippleTrack::fire_time_shift(SimTime revolution_start, double angle_since_start_rad) const {
  if (!(angle_since_start_rad > 0.0)) return SimTime::zero();
  const std::optional<double> rippling_s = seconds_to_turn(rippling_, revolution_start, angle_since_start_rad);
  const std::optional<double> ideal_s = seconds_to_turn(ideal_, revolution_start, angle_since_start_rad);
  if (!rippling_s || !ideal_s) return SimTime::zero();
  return std::chrono::round<SimTime>(std::chrono::duration<double>(*rippling_s - *ideal_s));
}

SimTime HeadRippleTrack::fire_time(SimTime revolution_start, SimTime nominal_time) const {
  const double angle_since_start_rad = ideal_.angle_rad(nominal_time) - ideal_.angle_rad(revolution_start);
  return nominal_time + fire_time_shift(revolution_start, angle_since_start_rad);
}

}  // namespace ldoem::motor
