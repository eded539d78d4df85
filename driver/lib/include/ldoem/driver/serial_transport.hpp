// RS-232 / RS-422 transport (spec 4.2): raw 8N1 at the endpoint's speed, host telegrams in
// ASCII hex with CRC-16, the LD's multi-package replies reassembled into one payload.
#pragma once

#include <memory>
#include <string>

#include "ldoem/driver/descriptor_transport.hpp"
#include "ldoem/protocol/serial_framing.hpp"

namespace ldoem::driver {

class SerialTransport final : public DescriptorTransport {
 public:
  // Opens the device (a tty or a pseudo terminal), sets raw mode, 8 data bits, no parity,
  // 1 stop bit, no flow control, and the speed (spec 4.2).
  static Expected<std::unique_ptr<SerialTransport>, DriverError> open(const SerialEndpoint& endpoint);

  Status send(ByteView payload, Deadline deadline) override;
  // Packages with a bad CRC, bad hex or out of sequence are dropped and counted.
  Expected<Bytes, DriverError> receive(Deadline deadline) override;
  TransportCounters counters() const override;

 private:
  SerialTransport(int fd, std::string name) : DescriptorTransport(fd, std::move(name)) {}

  protocol::SerialReplyReassembler reassembler_;
};

}  // namespace ldoem::driver
