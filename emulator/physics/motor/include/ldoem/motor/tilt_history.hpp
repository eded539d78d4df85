// The plate's tilt over the recent past, so that a beam measured after the fact can ask for the
// tilt at its own time (sweep_motion) or at its revolution's start. The motor models record
// into it themselves, only when the tilt changes: the ideal motor at each pulse (before and
// after the step), the dynamic one after each world step it integrates (it integrates only
// while the plate moves). Nobody samples on a clock, so an idle plate or an ideal motor costs
// nothing per time step (D9).
#pragma once

#include <ldoem/base/sim_time.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <deque>
#include <utility>

namespace ldoem::motor {

using base::SimTime;

class TiltHistory {
 public:
  // How far back tilt_at() answers; a revolution lasts at most 200 ms (5 Hz, spec 6).
  static constexpr SimTime kDefaultSpan = std::chrono::seconds(2);
  // At most this many records (16 bytes each, 2 MiB): 2 s of pulses at spec 6's 14.4 kHz limit,
  // two records each, need 57 600; a faster flood loses its oldest records instead of memory.
  static constexpr std::size_t kDefaultMaxRecords = 1u << 17;
  explicit TiltHistory(SimTime span = kDefaultSpan, std::size_t max_records = kDefaultMaxRecords)
      : span_(span), max_records_(std::max<std::size_t>(max_records, 2)) {}

  // The tilt was `tilt_rad` at `at` (records come in time order; two at one time are a step,
  // and more at one time keep only the first and the last).
  void record(SimTime at, double tilt_rad);

  // The tilt at `at`: linear between records, the oldest kept record before them, and
  // `current_rad` (the motor's tilt now) after the newest.
  [[nodiscard]] double tilt_at(SimTime at, double current_rad) const;

  [[nodiscard]] std::size_t size() const { return records_.size(); }

 private:
  SimTime span_;
  std::size_t max_records_;
  std::deque<std::pair<SimTime, double>> records_;
};

}  // namespace ldoem::motor
