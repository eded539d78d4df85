// Ethernet transport (spec 4.1): the LD is the TCP server on port 49152; one connection
// carries requests, replies and the profile stream.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "ldoem/driver/descriptor_transport.hpp"
#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::driver {

// Spec 6: S1 gives the connect 1 s.
inline constexpr std::chrono::milliseconds kTcpConnectTimeout{1000};
// A frame that started but got no byte for this long is given up and its bytes searched again
// for the next header (a frame cut short on the wire). S1 aborts after 35 ms (spec 6); we allow
// more, so a busy host or a slow link does not lose frames that are still coming.
inline constexpr std::chrono::milliseconds kTcpFrameGap{500};

class TcpTransport final : public DescriptorTransport {
 public:
  // Resolves the host, connects with `connect_timeout`, sets TCP_NODELAY (each telegram goes
  // out as it is written: S1 aborts a frame after a 35 ms gap, spec 6).
  static Expected<std::unique_ptr<TcpTransport>, DriverError> connect(
      const TcpEndpoint& endpoint, std::chrono::milliseconds connect_timeout = kTcpConnectTimeout);

  // One frame per spec 4.1, handed to the kernel in one write (D10).
  Status send(ByteView payload, Deadline deadline) override;
  // Frames with a bad checksum are dropped silently as S1 does, and counted; their bytes are
  // searched again for the next header, and a frame silent for kTcpFrameGap is given up, so
  // corrupted, truncated or garbage bytes cost only the frame they hit (resynchronisation).
  Expected<Bytes, DriverError> receive(Deadline deadline) override;
  TransportCounters counters() const override;

 private:
  TcpTransport(int fd, std::string name) : DescriptorTransport(fd, std::move(name)) {}

  protocol::TcpDeframer deframer_{protocol::kMaxTelegramPayload, protocol::TcpResync::rescan_dropped};
};

}  // namespace ldoem::driver
