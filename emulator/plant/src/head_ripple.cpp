#include "ldoem/plant/head_ripple.hpp"

namespace ldoem::plant {

void HeadRipple::set_target(SimTime now, double hz) {
  // Both heads are continuous across set_target, so the difference right now is the ripple
  // angle gathered so far; it is dropped from later deviations (see the header).
  offset_at_target_change_rad_ = rippling_.angle_rad(now) - ideal_.angle_rad(now);
  rippling_.set_target(now, hz);
  ideal_.set_target(now, hz);
}

double HeadRipple::deviation_rad(SimTime at) const {
  return rippling_.angle_rad(at) - ideal_.angle_rad(at) - offset_at_target_change_rad_;
}

}  // namespace ldoem::plant
