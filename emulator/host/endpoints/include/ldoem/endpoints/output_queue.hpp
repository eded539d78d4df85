// Bytes waiting for a slow peer (TCP connection, serial pty), bounded so that a host that stops
// reading cannot make the daemon grow without limit (the daemon drops such a TCP connection).
// D10: a non-empty queue means the previous telegram is still being sent, so a profile due now
// is skipped rather than queued behind it.
#pragma once

#include <cstddef>
#include <deque>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::endpoints {

// Beyond what the kernel's socket buffer already holds: 64 full-size profiles (D3: 5825 bytes).
inline constexpr std::size_t kDefaultOutputQueueBytes = 64 * 5825;

class OutputQueue {
 public:
  explicit OutputQueue(std::size_t max_bytes = kDefaultOutputQueueBytes) : max_bytes_(max_bytes) {}

  // Appends `bytes`; false (and nothing appended) when the bound would be exceeded.
  [[nodiscard]] bool push(protocol::ByteView bytes);
  // The oldest unsent bytes, as one contiguous piece (one whole telegram or its rest).
  protocol::ByteView front() const;
  // Marks `count` bytes of front() as sent.
  void consume(std::size_t count);
  void clear();

  bool empty() const { return size_bytes_ == 0; }
  std::size_t size_bytes() const { return size_bytes_; }
  std::size_t max_bytes() const { return max_bytes_; }

 private:
  std::size_t max_bytes_;
  std::deque<protocol::Bytes> chunks_;
  std::size_t front_offset_ = 0;
  std::size_t size_bytes_ = 0;
};

}  // namespace ldoem::endpoints
