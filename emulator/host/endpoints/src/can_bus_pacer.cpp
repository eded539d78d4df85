#include "ldoem/endpoints/can_bus_pacer.hpp"

#include <algorithm>

namespace ldoem::endpoints {

std::uint32_t can_bit_rate_bps(std::uint16_t bitrate_code) {
  switch (bitrate_code) {  // D1: SET_CONFIG key 0x0002 BITRATE
    case 1: return 125'000;
    case 2: return 250'000;
    case 3: return 500'000;
    case 4: return 1'000'000;
    default: return kDefaultCanBitRateBps;
  }
}

SimTime can_frame_duration(std::size_t data_bytes, std::uint32_t bit_rate_bps) {
  const std::uint64_t bits = kCanFrameOverheadBits + 8 * static_cast<std::uint64_t>(data_bytes);
  const std::uint64_t rate = std::max<std::uint32_t>(bit_rate_bps, 1);
  return SimTime((bits * 1'000'000'000ULL + rate - 1) / rate);
}

void CanBusPacer::push(SimTime now, const protocol::CanFrame& frame) {
  const SimTime starts = std::max(now, bus_free_at_);
  bus_free_at_ = starts + can_frame_duration(frame.payload().size(), bit_rate_bps_);
  queue_.emplace_back(bus_free_at_, frame);
  ++pending_by_id_[frame.id];
}

std::vector<protocol::CanFrame> CanBusPacer::take_due(SimTime now) {
  std::vector<protocol::CanFrame> due;
  while (!queue_.empty() && queue_.front().first <= now) {
    const protocol::CanFrame& frame = queue_.front().second;
    if (auto pending = pending_by_id_.find(frame.id); pending != pending_by_id_.end() && --pending->second == 0) {
      pending_by_id_.erase(pending);
    }
    due.push_back(frame);
    queue_.pop_front();
  }
  return due;
}

std::optional<SimTime> CanBusPacer::deadline() const {
  if (queue_.empty()) return std::nullopt;
  return queue_.front().first;
}

bool CanBusPacer::pending_for(std::uint32_t id) const { return pending_by_id_.contains(id); }

}  // namespace ldoem::endpoints
