// CAN transports (D1): telegrams as ISO 15765-2 messages on 11-bit identifiers, host to LD on
// the request id (default 0x6C0), LD to host on the response id (default 0x6C1).
//
// CanIsoTpTransport runs protocol/'s pure IsoTpSender / IsoTpReceiver over a CAN_RAW socket
// and feeds them CLOCK_MONOTONIC time here, at the edge. KernelIsoTpTransport uses the
// kernel's CAN_ISOTP socket where the host has one (`can:isotp:IFACE`).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include "ldoem/base/unique_fd.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::driver {

// Our flow control as a receiver. D1: BS 0, STmin 0 unless configured.
struct IsoTpOptions {
  std::uint8_t block_size = 0;
  std::chrono::microseconds st_min{0};
  bool pad_frames = false;  // D1: unpadded unless configured (then 0xCC)
  std::chrono::milliseconds timeout{1000};  // D1: N_Bs = N_Cr = 1000 ms
  // N_WFTmax: the LD's FC WAITs accepted in a row before a request is given up (issue 11).
  std::uint32_t max_wait_frames = protocol::kIsoTpDefaultMaxWaitFrames;
};

// Monotonic time as the ISO-TP state machines see it (they never read a clock themselves).
base::SimTime monotonic_now();

class CanIsoTpTransport final : public TelegramTransport {
 public:
  // socket(PF_CAN, SOCK_RAW, CAN_RAW), a kernel filter that passes only the response id, bind
  // to the interface.
  static Expected<std::unique_ptr<CanIsoTpTransport>, DriverError> open(const CanEndpoint& endpoint,
                                                                         IsoTpOptions options = {});

  ~CanIsoTpTransport() override;
  CanIsoTpTransport(const CanIsoTpTransport&) = delete;
  CanIsoTpTransport& operator=(const CanIsoTpTransport&) = delete;

  // Segments the telegram, honouring the device's flow control (BS, STmin, wait). Telegrams
  // that arrive meanwhile are kept for receive(). Errors: timeout (N_Bs or the deadline),
  // refused (FC overflow), busy (the interface's queue stayed full), system.
  Status send(ByteView payload, Deadline deadline) override;
  // Broken segment sequences are dropped and counted (D1).
  Expected<Bytes, DriverError> receive(Deadline deadline) override;
  void close() override;
  const std::string& name() const override { return name_; }
  TransportCounters counters() const override;

 private:
  CanIsoTpTransport(int fd, std::string name, const CanEndpoint& endpoint, IsoTpOptions options);
  Status write_frame(const protocol::CanFrame& frame, Deadline deadline);
  // Reads every frame waiting on the socket (after waiting until `wake` for the first one)
  // and dispatches them: FC to the sender, the rest to the receiver.
  Status pump(Deadline wake, Deadline deadline);
  Status dispatch(const protocol::CanFrame& frame, Deadline deadline);
  Status run_receiver_timer(Deadline deadline);

  base::UniqueFd fd_;
  std::string name_;
  protocol::IsoTpSender sender_;
  protocol::IsoTpReceiver receiver_;
  std::deque<Bytes> received_;
  TransportCounters counters_;
};

class KernelIsoTpTransport final : public TelegramTransport {
 public:
  // socket(PF_CAN, SOCK_DGRAM, CAN_ISOTP). Without can-isotp in the kernel: unsupported, with
  // a detail that names the user-space alternative (see kernel_isotp_unavailable).
  static Expected<std::unique_ptr<KernelIsoTpTransport>, DriverError> open(const CanEndpoint& endpoint,
                                                                            IsoTpOptions options = {});

  ~KernelIsoTpTransport() override;
  KernelIsoTpTransport(const KernelIsoTpTransport&) = delete;
  KernelIsoTpTransport& operator=(const KernelIsoTpTransport&) = delete;

  Status send(ByteView payload, Deadline deadline) override;
  Expected<Bytes, DriverError> receive(Deadline deadline) override;
  void close() override;
  const std::string& name() const override { return name_; }
  TransportCounters counters() const override { return counters_; }

 private:
  KernelIsoTpTransport(int fd, std::string name);

  base::UniqueFd fd_;
  std::string name_;
  TransportCounters counters_;
};

// The error open() returns when socket(PF_CAN, SOCK_DGRAM, CAN_ISOTP) fails with
// `errno_value` (EPROTONOSUPPORT, EAFNOSUPPORT ...): kind unsupported, detail pointing at the
// user-space endpoint, e.g. "... no CAN_ISOTP in this kernel; use can:vcan0 (user-space ISO-TP)".
DriverError kernel_isotp_unavailable(const CanEndpoint& endpoint, int errno_value);

}  // namespace ldoem::driver
