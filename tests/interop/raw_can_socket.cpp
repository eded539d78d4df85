#include "raw_can_socket.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace ldoem::interop {
namespace {

SocketError failure(const std::string& operation, const std::string& object, int errno_value) {
  return operation + " " + object + ": " + std::strerror(errno_value);
}

base::Unexpected<SocketError> unexpected(const std::string& operation, const std::string& object) {
  return base::Unexpected<SocketError>(failure(operation, object, errno));
}

// Closes the descriptor unless released; keeps open() free of repeated clean-up code.
struct FdGuard {
  int fd;
  ~FdGuard() {
    if (fd >= 0) ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

bool configure(int fd, const RawCanOptions& options) {
  const can_filter filter{options.receive_id, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
  if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) != 0) return false;
  const int enable = 1;
  if (setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &enable, sizeof enable) != 0) return false;
  if (options.receive_buffer_bytes) {
    const int bytes = *options.receive_buffer_bytes;
    // FORCE needs CAP_NET_ADMIN (root inside UML); plain SO_RCVBUF is capped by rmem_max.
    if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &bytes, sizeof bytes) != 0 &&
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &bytes, sizeof bytes) != 0) {
      return false;
    }
  }
  return true;
}

}  // namespace

base::Expected<RawCanSocket, SocketError> RawCanSocket::open(const std::string& interface_name,
                                                                 const RawCanOptions& options) {
  const int type = SOCK_RAW | SOCK_CLOEXEC | (options.non_blocking ? SOCK_NONBLOCK : 0);
  FdGuard guard{::socket(PF_CAN, type, CAN_RAW)};
  if (guard.fd < 0) return unexpected("socket(PF_CAN, CAN_RAW)", interface_name);
  if (!configure(guard.fd, options)) return unexpected("setsockopt", interface_name);
  const unsigned index = if_nametoindex(interface_name.c_str());
  if (index == 0) return unexpected("if_nametoindex", interface_name);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (bind(guard.fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    return unexpected("bind", interface_name);
  }
  return RawCanSocket(guard.release(), interface_name);
}

RawCanSocket::RawCanSocket(RawCanSocket&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), interface_name_(std::move(other.interface_name_)) {}

RawCanSocket& RawCanSocket::operator=(RawCanSocket&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    interface_name_ = std::move(other.interface_name_);
  }
  return *this;
}

RawCanSocket::~RawCanSocket() {
  if (fd_ >= 0) ::close(fd_);
}

base::Expected<bool, SocketError> RawCanSocket::write(const protocol::CanFrame& frame) {
  can_frame raw{};
  raw.can_id = frame.id;
  raw.len = static_cast<__u8>(frame.payload().size());
  std::memcpy(raw.data, frame.data.data(), raw.len);
  for (;;) {
    const ssize_t written = ::write(fd_, &raw, sizeof raw);
    if (written == static_cast<ssize_t>(sizeof raw)) return true;
    if (written < 0 && errno == EINTR) continue;
    // ENOBUFS: the interface's queue is full; like EAGAIN it clears once frames drain.
    if (written < 0 && (errno == EAGAIN || errno == ENOBUFS)) return false;
    return unexpected("write", interface_name_);
  }
}

base::Expected<ReadResult, SocketError> RawCanSocket::read() {
  can_frame raw{};
  iovec vector{&raw, sizeof raw};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(std::uint32_t))];
  msghdr message{};
  message.msg_iov = &vector;
  message.msg_iovlen = 1;
  message.msg_control = control;
  message.msg_controllen = sizeof control;
  ssize_t received;
  do {
    received = ::recvmsg(fd_, &message, 0);
  } while (received < 0 && errno == EINTR);
  ReadResult result;
  if (received < 0) {
    if (errno == EAGAIN) return result;
    return unexpected("recvmsg", interface_name_);
  }
  for (cmsghdr* header = CMSG_FIRSTHDR(&message); header != nullptr; header = CMSG_NXTHDR(&message, header)) {
    if (header->cmsg_level == SOL_SOCKET && header->cmsg_type == SO_RXQ_OVFL) {
      std::memcpy(&result.kernel_drops, CMSG_DATA(header), sizeof result.kernel_drops);
    }
  }
  protocol::CanFrame frame;
  frame.id = raw.can_id & CAN_SFF_MASK;
  frame.length = raw.len <= protocol::kCanMaxDataBytes ? raw.len : protocol::kCanMaxDataBytes;
  std::memcpy(frame.data.data(), raw.data, frame.length);
  result.frame = frame;
  return result;
}

int RawCanSocket::receive_buffer_bytes() const {
  int bytes = 0;
  socklen_t size = sizeof bytes;
  return getsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &bytes, &size) == 0 ? bytes : -1;
}

}  // namespace ldoem::interop
