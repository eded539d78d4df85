// Wall-clock limits on what a host may leave half done or hold (issue 11, docs/emulator.md
// "Limits"). Wall time, not simulated time: they are about the host's behaviour, which runs on
// the wall clock even with --virtual-time.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace ldoem::endpoints {

// Spec 6: S1 aborts a TCP frame after 35 ms of silence inside it (S4: 70 ms). The device is
// lenient on purpose (a loaded host or network may pause longer); what matters is that the
// start of a frame a host gave up on is not joined to the bytes it sends next.
inline constexpr std::chrono::milliseconds kDefaultInterByteTimeout{500};
// A connection that has not sent one complete telegram this long after connecting is closed
// (port scans, stuck or hostile connects holding descriptors; a driver speaks at once).
inline constexpr std::chrono::milliseconds kDefaultSilentTimeout{60'000};
// TCP connections one scanner serves at once (--max-clients). S1 uses one connection and the hub
// one per device; 64 leaves room for tools and tests beside them, and bounds what hosts can
// hold: each connection's output queue takes up to 372 800 bytes (64 of them: about 24 MB).
inline constexpr std::size_t kDefaultMaxTcpClients = 64;

struct HostLimits {
  std::chrono::milliseconds inter_byte_timeout = kDefaultInterByteTimeout;  // 0: never
  std::chrono::milliseconds silent_timeout = kDefaultSilentTimeout;         // TCP; 0: never
  // TCP: nothing received from the host this long closes the connection. 0 (the default):
  // never, since the LD keeps a quiet connection and the driver and hub do not reconnect.
  std::chrono::milliseconds idle_timeout{0};
  // TCP: connections served at once. A further one is accepted and closed at once (counted in
  // tcp_refused): the host protocol has no "busy" reply, and a closed connection tells a driver
  // at once instead of leaving it to time out in the listen backlog.
  std::size_t max_tcp_clients = kDefaultMaxTcpClients;
  bool operator==(const HostLimits&) const = default;
};

// Connection numbers tcp#1, tcp#2, ...: the next number not in use, 0 never (issue 11: the
// counter wrapped onto a live connection, and the new connection closed the old one).
class ConnectionIndices {
 public:
  explicit ConnectionIndices(std::uint32_t max_index = UINT32_MAX) : max_index_(max_index) {}
  // The next free index after the last one given, wrapping to 1 after max_index; nothing when
  // every index is in use. `in_use(i)` says whether i is taken.
  template <class InUse>
  std::optional<std::uint32_t> take(InUse in_use) {
    for (std::uint64_t tried = 0; tried < max_index_; ++tried) {
      const std::uint32_t index = next_;
      next_ = next_ >= max_index_ ? 1 : next_ + 1;
      if (!in_use(index)) return index;
    }
    return std::nullopt;
  }

 private:
  std::uint32_t max_index_;
  std::uint32_t next_ = 1;
};

}  // namespace ldoem::endpoints
