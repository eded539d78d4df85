// The D9 effect `head_dynamics` as the sensor sees it: how far the measuring head's true angle
// departs from the nominal grid the control unit places the points on.
//
// Decision (documented in docs/emulator.md): the control unit keeps firing points at their
// nominal times (revolution start + angle / 5760 * period, D7) and reports nominal angles (the
// DIRECTION / angle fields stay on the 1/16 deg grid, as the LD reports its encoder ticks). With
// head_dynamics the head's speed ripples (motor/head_drive.hpp DynamicHead), so at a point's time
// the mirror actually points at nominal + deviation, and the ray is cast there: the range is
// measured at a slightly different angle than the one reported.
//
// The deviation is DynamicHead::angle_rad(t) - IdealHead::angle_rad(t), both driven by the same
// target changes (the control unit's spin-ups and stops, told in Actions::head_target_hz), minus what the
// ripple had accumulated before the last target change: the head's zero mark re-aligns the
// encoder every revolution, so an old phase offset does not carry into a new speed epoch.
// Without the effect the plant builds no HeadRipple and casts at the nominal angles.
#pragma once

#include "ldoem/motor/head_drive.hpp"
#include "ldoem/protocol/sim_time.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::plant {

using protocol::SimTime;

class HeadRipple {
 public:
  explicit HeadRipple(const scene::HeadConfig& config) : rippling_(config), ideal_(config) {}

  // The head's target speed changes at `now` (0 stops it); call in time order.
  void set_target(SimTime now, double hz);
  // True angle minus nominal angle at `at` (radians, positive = ahead, counter-clockwise).
  double deviation_rad(SimTime at) const;

 private:
  motor::DynamicHead rippling_;
  motor::IdealHead ideal_;
  double offset_at_target_change_rad_ = 0.0;
};

}  // namespace ldoem::plant
