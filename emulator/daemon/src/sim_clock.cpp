#include "ldoem/daemon/sim_clock.hpp"

#include <algorithm>
#include <cmath>

namespace ldoem::daemon {
namespace {

// Half of int64 nanoseconds (146 years): a product or quotient of the time scale beyond it is
// clamped there instead of overflowing the conversion (undefined behaviour). The options keep
// the scale in 1e-6..1e6, so only a daemon that runs for decades could reach it.
constexpr double kLatestNanoseconds = static_cast<double>(SimTime::max().count() / 2);

SimTime::rep saturated_nanoseconds(double nanoseconds) {
  return static_cast<SimTime::rep>(std::clamp(nanoseconds, 0.0, kLatestNanoseconds));
}

}  // namespace

SimClock SimClock::scaled(WallTime start, double time_scale) { return SimClock(false, start, time_scale); }

SimClock SimClock::virtual_clock() { return SimClock(true, WallTime{}, 1.0); }

SimTime SimClock::now(WallTime wall) {
  if (!virtual_) {
    const auto elapsed = std::chrono::duration_cast<SimTime>(wall - start_);
    const auto scaled = SimTime(saturated_nanoseconds(std::floor(static_cast<double>(elapsed.count()) * time_scale_)));
    floor_ = std::max(floor_, scaled);
  }
  return floor_;
}

WallTime SimClock::wall_deadline(SimTime at, WallTime wall_now) const {
  if (virtual_) {
    return wall_now;
  }
  const double wall_ns = std::ceil(static_cast<double>(at.count()) / time_scale_);
  return start_ + std::chrono::duration_cast<WallTime::duration>(SimTime(saturated_nanoseconds(wall_ns)));
}

void SimClock::advance_to(SimTime at) { floor_ = std::max(floor_, at); }

DeadlineQueue::Key DeadlineQueue::add(SimTime at, Action action) {
  const Key key{at, next_sequence_++};
  entries_.emplace(key, std::move(action));
  return key;
}

void DeadlineQueue::cancel(const Key& key) { entries_.erase(key); }

std::optional<SimTime> DeadlineQueue::earliest() const {
  if (entries_.empty()) {
    return std::nullopt;
  }
  return entries_.begin()->first.first;
}

std::optional<std::pair<SimTime, DeadlineQueue::Action>> DeadlineQueue::pop_due(SimTime now) {
  if (entries_.empty() || entries_.begin()->first.first > now) {
    return std::nullopt;
  }
  auto node = entries_.extract(entries_.begin());
  return std::make_pair(node.key().first, std::move(node.mapped()));
}

}  // namespace ldoem::daemon
