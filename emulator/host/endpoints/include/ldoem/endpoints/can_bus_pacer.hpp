// The D9 effect `bus_timing`: our CAN frames leave at the pace of the configured bit rate (D1,
// SET_CONFIG key 0x0002 BITRATE) instead of as fast as the socket takes them. vcan has no bit
// rate, so the daemon holds each frame back until a real bus would have finished sending it.
//
// Frame length: a classic CAN 2.0A data frame with n data bytes is counted as 47 + 8 n bits
// (SOF, 11-bit identifier, RTR, IDE, r0, DLC, data, 15-bit CRC, CRC and ACK delimiters, ACK slot,
// EOF and the 3-bit interframe space). Stuff bits are left out on purpose: their number depends
// on the data, and the nominal figure keeps the timing a pure function of the DLC (an 8-byte
// frame is 111 bits, 111 us at 1 Mbit/s; worst-case stuffing would add up to 24 bits).
// Only our own frames are paced; the host's frames (requests, its flow control) arrive when the
// host sends them and are not charged to the bus.
//
// Pure: frames and simulated time in, frames out at their due times; no clock is read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::endpoints {

using base::SimTime;

inline constexpr std::uint32_t kCanFrameOverheadBits = 47;  // nominal, no stuff bits (see above)
inline constexpr std::uint32_t kDefaultCanBitRateBps = 1'000'000;  // D1: the paper's set-up

// D1 BITRATE code -> bits per second: 1 = 125k, 2 = 250k, 3 = 500k, 4 = 1M. Other codes (the
// control unit refuses them in SET_CONFIG, D2) give the default 1 Mbit/s.
std::uint32_t can_bit_rate_bps(std::uint16_t bitrate_code);

// (47 + 8 n) bits at `bit_rate_bps`, rounded up to whole nanoseconds (exact for the D1 rates).
SimTime can_frame_duration(std::size_t data_bytes, std::uint32_t bit_rate_bps);

class CanBusPacer {
 public:
  explicit CanBusPacer(std::uint32_t bit_rate_bps = kDefaultCanBitRateBps) : bit_rate_bps_(bit_rate_bps) {}

  // Takes effect for frames pushed from now on (frames already on their way keep their times).
  void set_bit_rate(std::uint32_t bit_rate_bps) { bit_rate_bps_ = bit_rate_bps; }
  std::uint32_t bit_rate_bps() const { return bit_rate_bps_; }

  // Queues `frame` behind every frame already queued: it starts when the bus is free (now at the
  // earliest) and leaves (is handed to the socket) when its last bit is on the bus.
  void push(SimTime now, const protocol::CanFrame& frame);
  // The frames whose last bit is on the bus by `now`, in order.
  std::vector<protocol::CanFrame> take_due(SimTime now);
  // When the oldest queued frame leaves; nothing when the queue is empty.
  std::optional<SimTime> deadline() const;

  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }
  // Frames with identifier `id` still queued (D10: that host's previous telegram is still being sent).
  bool pending_for(std::uint32_t id) const;
  // The time the bus is free again after the last queued frame.
  SimTime bus_free_at() const { return bus_free_at_; }

 private:
  std::uint32_t bit_rate_bps_;
  SimTime bus_free_at_{0};
  std::deque<std::pair<SimTime, protocol::CanFrame>> queue_;  // (leaves at, frame), in time order
  std::map<std::uint32_t, std::size_t> pending_by_id_;
};

}  // namespace ldoem::endpoints
