// A bare CAN_RAW socket for the interop test (a probe frame) and the vcan benchmark: one
// receive identifier, optional non-blocking mode, receive buffer size and the kernel's drop
// counter (SO_RXQ_OVFL). The benchmark needs the raw descriptor and the drop counter, which the
// emulator's and the driver's sockets keep to themselves, so this is its own small edge.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::interop {

struct RawCanOptions {
  std::uint32_t receive_id = 0;          // the kernel filter passes only this 11-bit id
  bool non_blocking = false;
  std::optional<int> receive_buffer_bytes;  // SO_RCVBUFFORCE, else SO_RCVBUF; kernel default if unset
};

// One line that names the operation and the object, e.g. "bind vcan0: No such device".
using SocketError = std::string;

// What one read found.
struct ReadResult {
  std::optional<protocol::CanFrame> frame;  // nothing: would block (non-blocking mode)
  std::uint32_t kernel_drops = 0;           // SO_RXQ_OVFL: frames the socket's queue refused so far
};

class RawCanSocket {
 public:
  static base::Expected<RawCanSocket, SocketError> open(const std::string& interface_name,
                                                            const RawCanOptions& options);
  RawCanSocket(RawCanSocket&& other) noexcept;
  RawCanSocket& operator=(RawCanSocket&& other) noexcept;
  RawCanSocket(const RawCanSocket&) = delete;
  RawCanSocket& operator=(const RawCanSocket&) = delete;
  ~RawCanSocket();

  // true: written; false: the socket would block (non-blocking mode only); error otherwise.
  base::Expected<bool, SocketError> write(const protocol::CanFrame& frame);
  base::Expected<ReadResult, SocketError> read();
  // The receive buffer the kernel granted (SO_RCVBUF reads back twice the request).
  int receive_buffer_bytes() const;
  int fd() const { return fd_; }

 private:
  explicit RawCanSocket(int fd, std::string interface_name) : fd_(fd), interface_name_(std::move(interface_name)) {}
  int fd_ = -1;
  std::string interface_name_;
};

}  // namespace ldoem::interop
