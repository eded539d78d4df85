// Simulated time as an endpoint sees it (D7): what time it is, and deadlines it wants to be
// called back at (ISO-TP N_Bs/N_Cr and STmin, the D9 bus pacer). The daemon's clock and
// deadline queue implement it; a test can implement it with a plain counter.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <utility>

#include "ldoem/base/sim_time.hpp"

namespace ldoem::endpoints {

using base::SimTime;
using WallTime = std::chrono::steady_clock::time_point;

class Scheduler {
 public:
  using Key = std::pair<SimTime, std::uint64_t>;
  using Action = std::function<void(SimTime now)>;

  virtual ~Scheduler() = default;
  // Simulated time now; never less than before.
  virtual SimTime now() = 0;
  // Simulated time at a CLOCK_MONOTONIC instant (a kernel timestamp, e.g. a gpio edge's).
  virtual SimTime at_wall_time(WallTime wall) = 0;
  // `action` runs once simulated time reaches `at`. A deadline nobody needs any more must be
  // cancelled: with virtual time the daemon jumps to the earliest one (D7).
  virtual Key add(SimTime at, Action action) = 0;
  virtual void cancel(const Key& key) = 0;
};

}  // namespace ldoem::endpoints
