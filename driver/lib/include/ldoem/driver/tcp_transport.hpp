// Ethernet transport (spec 4.1): the LD is the TCP server on port 49152; one connection
// carries requests, replies and the profile stream.
#pragma once

#include <chrono>
#include <deque>
#include <memory>
#include <string>

#include "ldoem/base/unique_fd.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::driver {

// Spec 6: S1 gives the connect 1 s.
inline constexpr std::chrono::milliseconds kTcpConnectTimeout{1000};
// A frame that started but got no byte for this long is given up and its bytes searched again
// for the next header (a frame cut short on the wire). S1 aborts after 35 ms (spec 6); we allow
// more, so a busy host or a slow link does not lose frames that are still coming.
inline constexpr std::chrono::milliseconds kTcpFrameGap{500};

class TcpTransport final : public Transport {
 public:
  // Resolves the host, connects with `connect_timeout`, sets TCP_NODELAY (each telegram goes
  // out as it is written: S1 aborts a frame after a 35 ms gap, spec 6).
  static Expected<std::unique_ptr<TcpTransport>, DriverError> connect(
      const TcpEndpoint& endpoint, std::chrono::milliseconds connect_timeout = kTcpConnectTimeout);

  ~TcpTransport() override;
  TcpTransport(const TcpTransport&) = delete;
  TcpTransport& operator=(const TcpTransport&) = delete;

  // One frame per spec 4.1, handed to the kernel in one write (D10).
  Status send(ByteView payload, Deadline deadline) override;
  // Frames with a bad checksum are dropped silently as S1 does, and counted; their bytes are
  // searched again for the next header, and a frame silent for kTcpFrameGap is given up, so
  // corrupted, truncated or garbage bytes cost only the frame they hit (resynchronisation).
  Expected<Bytes, DriverError> receive(Deadline deadline) override;
  std::vector<Bytes> take_arrived(std::size_t limit) override { return take_arrived_now(*this, limit); }
  void close() override;
  const std::string& name() const override { return name_; }
  TransportCounters counters() const override;

 private:
  TcpTransport(int fd, std::string name);

  base::UniqueFd fd_;
  std::string name_;
  protocol::TcpDeframer deframer_{protocol::kMaxTelegramPayload, protocol::TcpResync::rescan_dropped};
  std::deque<Bytes> received_;
  TransportCounters counters_;
};

}  // namespace ldoem::driver
