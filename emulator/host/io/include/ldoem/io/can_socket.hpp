// A SocketCAN CAN_RAW endpoint carrying classic frames (D1: CAN 2.0A, 11-bit ids, <= 8 bytes).
// It moves frames only; ISO-TP lives in protocol/. Non-blocking: register fd() with the
// EventLoop and call receive() until it returns nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/io/io_error.hpp"
#include "ldoem/base/unique_fd.hpp"
#include "ldoem/protocol/can_frame.hpp"

namespace ldoem::io {

// A kernel receive filter (CAN_RAW_FILTER): a frame passes when (frame id & mask) == (id & mask).
struct CanIdFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = protocol::kCanStandardIdMask;
};

// Matches exactly one 11-bit identifier, data frames only (no RTR, no 29-bit ids).
CanIdFilter exact_standard_id(std::uint32_t id);

enum class SendOutcome {
  sent,
  queue_full,  // the device's transmit queue is full (ENOBUFS/EAGAIN): retry when writable
};

class CanRawSocket {
 public:
  // socket(PF_CAN, SOCK_RAW, CAN_RAW) bound to `interface_name`, non-blocking, close-on-exec.
  // Empty `filters`: every frame; otherwise only frames passing one of them.
  static IoResult<CanRawSocket> open(std::string_view interface_name,
                                     std::span<const CanIdFilter> filters = {});

  IoStatus set_filters(std::span<const CanIdFilter> filters);

  // The next classic 11-bit data frame, or nothing when none is queued. Frames this endpoint
  // cannot carry (29-bit, remote, error frames) are dropped and counted.
  IoResult<std::optional<protocol::CanFrame>> receive();
  // Rejects (EINVAL) a frame with an id over 11 bits or more than 8 bytes before any I/O.
  IoResult<SendOutcome> send(const protocol::CanFrame& frame);

  int fd() const { return fd_.get(); }
  const std::string& interface_name() const { return interface_name_; }
  std::uint64_t dropped_foreign_frames() const { return dropped_foreign_frames_; }

 private:
  CanRawSocket(base::UniqueFd fd, std::string interface_name)
      : fd_(std::move(fd)), interface_name_(std::move(interface_name)) {}

  base::UniqueFd fd_;
  std::string interface_name_;
  std::uint64_t dropped_foreign_frames_ = 0;
};

}  // namespace ldoem::io
