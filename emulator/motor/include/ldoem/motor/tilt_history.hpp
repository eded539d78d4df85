// The plate's tilt over the recent past, so that a beam measured after the fact can ask for the
// tilt at its own time (sweep_motion) or at its revolution's start. The motor models record
// into it themselves, only when the tilt changes: the ideal motor at each pulse (before and
// after the step), the dynamic one after each world step it integrates (it integrates only
// while the plate moves). Nobody samples on a clock, so an idle plate or an ideal motor costs
// nothing per time step (D9).
#pragma once

#include <ldoem/protocol/sim_time.hpp>

#include <chrono>
#include <deque>
#include <utility>

namespace ldoem::motor {

using protocol::SimTime;

class TiltHistory {
 public:
  // How far back tilt_at() answers; a revolution lasts at most 200 ms (5 Hz, spec 6).
  static constexpr SimTime kDefaultSpan = std::chrono::seconds(2);
  explicit TiltHistory(SimTime span = kDefaultSpan) : span_(span) {}

  // The tilt was `tilt_rad` at `at` (records come in time order; two at one time are a step).
  void record(SimTime at, double tilt_rad);

  // The tilt at `at`: linear between records, the oldest kept record before them, and
  // `current_rad` (the motor's tilt now) after the newest.
  [[nodiscard]] double tilt_at(SimTime at, double current_rad) const;

  [[nodiscard]] std::size_t size() const { return records_.size(); }

 private:
  SimTime span_;
  std::deque<std::pair<SimTime, double>> records_;
};

}  // namespace ldoem::motor
