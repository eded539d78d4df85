// The CAN frames the interface's queue refused (vcan or a real controller whose TX queue is full
// because nobody acknowledges), bounded (issue 11: it grew without limit). When a batch of frames
// does not fit, the whole batch is dropped, the newest frames rather than the oldest: the oldest
// belong to a message already partly on the bus, and a host's ISO-TP receiver gives up a message
// with missing frames on its own (N_Cr, D1), exactly as on a bus that loses frames.
// docs/decisions-local.md L-limits-2.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>

#include "ldoem/protocol/can_frame.hpp"

namespace ldoem::endpoints {

// Five full-size profiles with BS 0 (D3: 5816 bytes, 832 frames each).
inline constexpr std::size_t kMaxCanBacklogFrames = 4096;

class CanFrameBacklog {
 public:
  explicit CanFrameBacklog(std::size_t max_frames = kMaxCanBacklogFrames) : max_frames_(max_frames) {}

  // Appends every frame of `frames`, or none of them when they would not fit (counted).
  bool push(std::span<const protocol::CanFrame> frames) {
    if (frames.size() > max_frames_ - std::min(frames_.size(), max_frames_)) {
      dropped_ += frames.size();
      return false;
    }
    frames_.insert(frames_.end(), frames.begin(), frames.end());
    return true;
  }
  bool empty() const { return frames_.empty(); }
  std::size_t size() const { return frames_.size(); }
  const protocol::CanFrame& front() const { return frames_.front(); }
  void pop_front() { frames_.pop_front(); }
  std::size_t max_frames() const { return max_frames_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::size_t max_frames_;
  std::deque<protocol::CanFrame> frames_;
  std::uint64_t dropped_ = 0;
};

}  // namespace ldoem::endpoints
