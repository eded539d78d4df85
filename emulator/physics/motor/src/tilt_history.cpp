#include <ldoem/motor/tilt_history.hpp>

#include <algorithm>
#include <iterator>

namespace ldoem::motor {

void TiltHistory::record(SimTime at, double tilt_rad) {
  const std::size_t count = records_.size();
  if (count >= 2 && records_.back().second == tilt_rad && records_[count - 2].second == tilt_rad) {
    // Steady stretches keep only their two ends, so an idle plate costs no memory.
    records_.back().first = std::max(records_.back().first, at);
  } else if (count >= 2 && records_.back().first >= at && records_[count - 2].first >= at) {
    // Many steps at one instant (a register flood while a virtual clock stands still, issue 11):
    // tilt_at() sees only the first record of an instant (the way in) and the last (the way
    // out), so the ones between are overwritten instead of kept.
    records_.back().second = tilt_rad;
  } else {
    records_.emplace_back(at, tilt_rad);
  }
  while (records_.size() > 2 && records_[1].first < at - span_) records_.pop_front();
  // A flood spread over distinct instants inside the span (a tiny --time-scale) is bounded by
  // count: the oldest records go first, and tilt_at() answers with the oldest kept one before them.
  while (records_.size() > max_records_) records_.pop_front();
}

double TiltHistory::tilt_at(SimTime at, double current_rad) const {
  if (records_.empty() || at >= records_.back().first) return current_rad;
  if (at <= records_.front().first) return records_.front().second;
  // The last record at or before `at`: a pulse records two at one time, and the later one
  // (after the step) holds from then on.
  const auto after = std::upper_bound(records_.begin(), records_.end(), at,
                                      [](SimTime t, const auto& record) { return t < record.first; });
  const auto before = std::prev(after);
  const double span_ns = static_cast<double>((after->first - before->first).count());
  if (span_ns <= 0.0) return before->second;
  const double fraction = static_cast<double>((at - before->first).count()) / span_ns;
  return before->second + fraction * (after->second - before->second);
}

}  // namespace ldoem::motor
