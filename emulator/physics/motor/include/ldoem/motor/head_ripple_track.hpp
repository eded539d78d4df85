// D9 head_dynamics as the sensor sees it, the one model shared by the daemon and the benchmarks.
//
// The LD fires a point on each encoder tick, so every point lies exactly at its nominal angle
// (the 1/16 deg grid the profile reports); the speed ripple changes *when* the head reaches that
// angle. The index mark re-aligns the encoder once per revolution, so the shift is counted from
// the revolution's start: a point `angle_since_start_rad` into a revolution fires when the
// rippling head (DynamicHead) has turned that far since the start, instead of when the ideal head
// (IdealHead, same spin-ups) has. The shift matters wherever a point's own time does: the tilt
// under sweep_motion, and the scene's state at that time. Without head_dynamics nobody builds a
// HeadRippleTrack and points fire at their nominal times.
#pragma once

#include <ldoem/motor/head_drive.hpp>

namespace ldoem::motor {

class HeadRippleTrack {
 public:
  explicit HeadRippleTrack(const scene::HeadConfig& config) : rippling_(config), ideal_(config) {}

  // The head's target speed changes at `now` (0 stops it); call in time order.
  void set_target(SimTime now, double hz);

  // When the point `angle_since_start_rad` (>= 0) into the revolution that starts at
  // `revolution_start` fires, minus when it would fire on the ideal head (positive = later).
  // Zero at the revolution's start, while the head spins up (the ripple starts once the target
  // is held) and when the head stands still.
  [[nodiscard]] SimTime fire_time_shift(SimTime revolution_start, double angle_since_start_rad) const;

  // When the point the control unit times at `nominal_time` (the ideal head's time for its angle,
  // in the revolution that starts at `revolution_start`) really fires.
  [[nodiscard]] SimTime fire_time(SimTime revolution_start, SimTime nominal_time) const;

  [[nodiscard]] const HeadDrive& rippling_head() const { return rippling_; }

 private:
  DynamicHead rippling_;
  IdealHead ideal_;
};

}  // namespace ldoem::motor
