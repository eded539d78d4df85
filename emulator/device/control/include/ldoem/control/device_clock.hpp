// The LD's 16-bit millisecond clock (spec 2.3, 3.3): the clock GET_SYNC_CLOCK reads, the
// SET_TIME services load, and TSTART/TEND are stamped with.
#pragma once

#include <cstdint>

#include "ldoem/base/sim_time.hpp"

namespace ldoem::control {

// value(now) = (offset_ms + floor(now in ms)) mod 65536: it ticks with simulated time (D7) and
// wraps after 65.536 s. Only the offset is state.
class DeviceClock {
 public:
  // A clock that reads `value_ms` at `now` (power-up and DO_RESET 0/1 use 0, D4).
  static DeviceClock reading(base::SimTime now, std::uint16_t value_ms);

  std::uint16_t value_at(base::SimTime now) const;
  // SET_TIME_ABS: from `now` on the clock reads value_ms.
  void set(base::SimTime now, std::uint16_t value_ms);
  // SET_TIME_REL: the signed delta wraps modulo 65536 (spec 3.3 [I]).
  void add(std::int16_t delta_ms);

  std::uint16_t offset_ms() const { return offset_ms_; }
  bool operator==(const DeviceClock&) const = default;

 private:
  std::uint16_t offset_ms_ = 0;
};

// floor(now / 1 ms), also for times before the epoch.
std::int64_t floor_ms(base::SimTime now);

}  // namespace ldoem::control
