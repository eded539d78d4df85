// The simulated clock (D7) and the daemon's queue of simulated-time deadlines.
//
// Scaled mode: sim_time = (wall_monotonic - start) * time_scale; a simulated deadline becomes
// the wall time start + deadline / time_scale (rounded up, so that it is never early).
// Virtual mode (--virtual-time): simulated time only moves when the daemon jumps it to the next
// deadline because nothing else is ready; the whole scan runs as fast as the CPU allows and does
// not depend on the machine's speed, except where hosts race it over sockets.
// Both modes never go backwards: now() is monotonic even when the wall clock is read late.
// Pure: the wall time is a parameter, never read here.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <utility>

#include "ldoem/base/sim_time.hpp"

namespace ldoem::daemon {

using base::SimTime;
using WallTime = std::chrono::steady_clock::time_point;

class SimClock {
 public:
  static SimClock scaled(WallTime start, double time_scale);
  static SimClock virtual_clock();

  bool is_virtual() const { return virtual_; }
  double time_scale() const { return time_scale_; }

  // Simulated time at `wall` (scaled) or the current virtual time; never less than before.
  SimTime now(WallTime wall);
  // Scaled mode: when the wall clock reaches `at`. Virtual mode: `wall_now` (due at once).
  WallTime wall_deadline(SimTime at, WallTime wall_now) const;
  // Moves simulated time forward to `at` (no-op for an earlier time). In scaled mode this only
  // raises the floor now() returns: a wall timer that fired a little early still counts as due.
  void advance_to(SimTime at);

 private:
  SimClock(bool is_virtual, WallTime start, double time_scale)
      : virtual_(is_virtual), start_(start), time_scale_(time_scale) {}

  bool virtual_;
  WallTime start_;
  double time_scale_;
  SimTime floor_{0};
};

// Deadlines in simulated time with their actions, fired in (time, insertion) order.
class DeadlineQueue {
 public:
  using Action = std::function<void(SimTime now)>;

  using Key = std::pair<SimTime, std::uint64_t>;
  // Returns the entry's key for cancel().
  Key add(SimTime at, Action action);
  // Removes an entry that has not fired yet (nothing if it has). A deadline nobody needs any more
  // must not stay queued: with virtual time the loop jumps to the earliest one (D7), so a stale
  // entry would move simulated time for nothing.
  void cancel(const Key& key);
  std::optional<SimTime> earliest() const;
  // Removes and returns the earliest action due at `now`, if any (one at a time, so that an
  // action may add new deadlines, even ones due at once).
  std::optional<std::pair<SimTime, Action>> pop_due(SimTime now);
  std::size_t size() const { return entries_.size(); }

 private:
  std::map<std::pair<SimTime, std::uint64_t>, Action> entries_;
  std::uint64_t next_sequence_ = 0;
};

}  // namespace ldoem::daemon
