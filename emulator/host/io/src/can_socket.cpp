#include "ldoem/io/can_socket.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "ldoem/base/endpoint.hpp"

namespace ldoem::io {
namespace {

IoStatus apply_filters(int fd, const std::string& interface_name,
                       std::span<const CanIdFilter> filters) {
  std::vector<can_filter> kernel_filters;
  kernel_filters.reserve(filters.size());
  for (const CanIdFilter& filter : filters) {
    kernel_filters.push_back(can_filter{filter.id, filter.mask});
  }
  // An empty list means "everything": the kernel's default single pass-all filter.
  if (kernel_filters.empty()) {
    kernel_filters.push_back(can_filter{0, 0});
  }
  const auto size = static_cast<socklen_t>(kernel_filters.size() * sizeof(can_filter));
  if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, kernel_filters.data(), size) != 0) {
    return io_failure(last_system_error("setsockopt CAN_RAW_FILTER", interface_name));
  }
  return Done{};
}

bool is_classic_standard_data_frame(const can_frame& frame) {
  return (frame.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) == 0 &&
         frame.len <= CAN_MAX_DLEN;
}

}  // namespace

CanIdFilter exact_standard_id(std::uint32_t id) {
  // Including the EFF and RTR flag bits in the mask makes extended and remote frames fail it.
  return CanIdFilter{id & CAN_SFF_MASK, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
}

IoResult<CanRawSocket> CanRawSocket::open(std::string_view interface_name,
                                          std::span<const CanIdFilter> filters) {
  std::string name(interface_name);
  if (name.empty() || name.size() >= IFNAMSIZ) {
    return io_failure(IoError{"open", name, EINVAL, "not a valid interface name"});
  }
  base::UniqueFd fd(::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW));
  if (!fd.valid()) {
    if (errno == EAFNOSUPPORT) {
      // The bare strerror leaves the user guessing; say what is missing and how to get it.
      return io_failure(IoError{"socket PF_CAN", name, EAFNOSUPPORT, std::string(std::strerror(EAFNOSUPPORT)) + "; " + base::can_unsupported_hint()});
    }
    return io_failure(last_system_error("socket PF_CAN", name));
  }
  const unsigned index = ::if_nametoindex(name.c_str());
  if (index == 0) {
    return io_failure(last_system_error("if_nametoindex", name));
  }
  if (IoStatus status = apply_filters(fd.get(), name, filters); !status) {
    return io_failure(status.error());
  }
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    return io_failure(last_system_error("bind", name));
  }
  return CanRawSocket(std::move(fd), std::move(name));
}

IoStatus CanRawSocket::set_filters(std::span<const CanIdFilter> filters) {
  return apply_filters(fd_.get(), interface_name_, filters);
}

IoResult<std::optional<protocol::CanFrame>> CanRawSocket::receive() {
  for (;;) {
    can_frame frame{};
    const ssize_t got = ::read(fd_.get(), &frame, sizeof frame);
    if (got < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        return std::optional<protocol::CanFrame>{};
      }
      if (errno == EINTR) {
        continue;
      }
      return io_failure(last_system_error("read", interface_name_));
    }
    if (got != static_cast<ssize_t>(sizeof frame) || !is_classic_standard_data_frame(frame)) {
      ++dropped_foreign_frames_;
      continue;
    }
    protocol::CanFrame result;
    result.id = frame.can_id & CAN_SFF_MASK;
    result.length = frame.len;
    std::memcpy(result.data.data(), frame.data, frame.len);
    return std::optional<protocol::CanFrame>(result);
  }
}

IoResult<SendOutcome> CanRawSocket::send(const protocol::CanFrame& frame) {
  if ((frame.id & ~protocol::kCanStandardIdMask) != 0) {
    return io_failure(IoError{"write", interface_name_, EINVAL,
                              "identifier " + std::to_string(frame.id) + " needs more than 11 bits"});
  }
  if (frame.length > protocol::kCanMaxDataBytes) {
    return io_failure(IoError{"write", interface_name_, EINVAL,
                              "a classic frame holds at most 8 bytes, not " +
                                  std::to_string(frame.length)});
  }
  can_frame kernel_frame{};
  kernel_frame.can_id = frame.id;
  kernel_frame.len = frame.length;
  std::memcpy(kernel_frame.data, frame.data.data(), frame.length);
  for (;;) {
    const ssize_t written = ::write(fd_.get(), &kernel_frame, sizeof kernel_frame);
    if (written == static_cast<ssize_t>(sizeof kernel_frame)) {
      return SendOutcome::sent;
    }
    if (written >= 0) {
      return io_failure(IoError{"write", interface_name_, EIO, "short write of a CAN frame"});
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno == ENOBUFS || errno == EAGAIN || errno == EWOULDBLOCK) {
      return SendOutcome::queue_full;
    }
    return io_failure(last_system_error("write", interface_name_));
  }
}

}  // namespace ldoem::io
