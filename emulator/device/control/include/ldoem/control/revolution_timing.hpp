// When things happen on a head spinning at a steady integer speed (lead decision 4, D7):
// revolution k of an epoch (the time the head reached its speed) covers
// [epoch + k/f, epoch + (k+1)/f), with head angle 0 (+x, D5) at its start. Times are computed
// from the epoch in exact integer nanoseconds (floor), never accumulated, so nothing drifts.
#pragma once

#include <cstdint>

#include "ldoem/base/sim_time.hpp"

namespace ldoem::control {

// The time the head passes `angle_unwrapped_ticks` (may exceed 5760: the next revolution) in
// revolution `revolution` of the epoch. Precondition: speed_hz > 0.
base::SimTime revolution_time(base::SimTime epoch, std::uint16_t speed_hz, std::uint64_t revolution,
                                  std::uint32_t angle_unwrapped_ticks);

// The first revolution of the epoch that starts at or after `t` (0 for t <= epoch).
std::uint64_t first_revolution_starting_at_or_after(base::SimTime epoch, std::uint16_t speed_hz,
                                                    base::SimTime t);

}  // namespace ldoem::control
