#include "raw_channels.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

namespace ldoem::conformance {
namespace {

using base::Expected;
using base::Unexpected;

Unexpected<RawError> sys_error(const std::string& operation, const std::string& object, int error_number) {
  return Unexpected<RawError>(operation + " " + object + ": " + std::strerror(error_number));
}

int remaining_ms(Deadline deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - driver::Clock::now());
  return left.count() < 0 ? 0 : static_cast<int>(left.count());
}

Expected<std::monostate, RawError> write_all(int fd, ByteView bytes, const std::string& object) {
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN) {
        pollfd p{fd, POLLOUT, 0};
        ::poll(&p, 1, 100);
        continue;
      }
      return sys_error("write", object, errno);
    }
    written += static_cast<std::size_t>(n);
  }
  return std::monostate{};
}

}  // namespace

FileDescriptor::~FileDescriptor() {
  if (fd_ >= 0) ::close(fd_);
}

FileDescriptor& FileDescriptor::operator=(FileDescriptor&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.release();
  }
  return *this;
}

int FileDescriptor::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

Expected<RawTcpSession, RawError> RawTcpSession::connect(const driver::TcpEndpoint& endpoint, Deadline deadline) {
  const std::string object = "tcp:" + endpoint.host + ":" + std::to_string(endpoint.port);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int resolved = ::getaddrinfo(endpoint.host.c_str(), std::to_string(endpoint.port).c_str(), &hints, &found);
  if (resolved != 0) return Unexpected<RawError>("resolve " + object + ": " + ::gai_strerror(resolved));
  FileDescriptor fd(::socket(found->ai_family, found->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (fd.get() < 0) {
    ::freeaddrinfo(found);
    return sys_error("socket", object, errno);
  }
  const int connected = ::connect(fd.get(), found->ai_addr, found->ai_addrlen);
  const int connect_errno = errno;
  ::freeaddrinfo(found);
  if (connected < 0 && connect_errno != EINPROGRESS) return sys_error("connect", object, connect_errno);
  pollfd p{fd.get(), POLLOUT, 0};
  if (::poll(&p, 1, remaining_ms(deadline)) <= 0) return Unexpected<RawError>("connect " + object + ": timeout");
  int so_error = 0;
  socklen_t length = sizeof so_error;
  ::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &so_error, &length);
  if (so_error != 0) return sys_error("connect", object, so_error);
  const int one = 1;
  ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return RawTcpSession(std::move(fd));
}

Expected<std::monostate, RawError> RawTcpSession::write(ByteView bytes) {
  return write_all(fd_.get(), bytes, "raw tcp session");
}

Expected<std::optional<Bytes>, RawError> RawTcpSession::receive(Deadline deadline) {
  while (received_.empty()) {
    pollfd p{fd_.get(), POLLIN, 0};
    const int ready = ::poll(&p, 1, remaining_ms(deadline));
    if (ready < 0 && errno != EINTR) return sys_error("poll", "raw tcp session", errno);
    if (ready <= 0) {
      if (driver::Clock::now() >= deadline) return std::optional<Bytes>{};
      continue;
    }
    std::uint8_t buffer[4096];
    const ssize_t n = ::read(fd_.get(), buffer, sizeof buffer);
    if (n == 0) return Unexpected<RawError>("read raw tcp session: connection closed by the peer");
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      return sys_error("read", "raw tcp session", errno);
    }
    for (auto& event : deframer_.feed(ByteView(buffer, static_cast<std::size_t>(n)))) {
      if (auto* telegram = std::get_if<protocol::Telegram>(&event)) received_.push_back(std::move(telegram->payload));
    }
  }
  Bytes payload = std::move(received_.front());
  received_.pop_front();
  return std::optional<Bytes>(std::move(payload));
}

Expected<RawSerialWriter, RawError> RawSerialWriter::open(const driver::SerialEndpoint& endpoint) {
  FileDescriptor fd(::open(endpoint.path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC | O_NONBLOCK));
  if (fd.get() < 0) return sys_error("open", endpoint.path, errno);
  return RawSerialWriter(std::move(fd));
}

Expected<std::monostate, RawError> RawSerialWriter::write(ByteView bytes) {
  return write_all(fd_.get(), bytes, "raw serial writer");
}

Expected<RawCanWriter, RawError> RawCanWriter::open(const driver::CanEndpoint& endpoint) {
  FileDescriptor fd(::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW));
  if (fd.get() < 0) return sys_error("socket CAN_RAW", endpoint.interface, errno);
  // Write only: receive nothing on this socket.
  ::setsockopt(fd.get(), SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0);
  ifreq request{};
  std::strncpy(request.ifr_name, endpoint.interface.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd.get(), SIOCGIFINDEX, &request) < 0) return sys_error("SIOCGIFINDEX", endpoint.interface, errno);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = request.ifr_ifindex;
  if (::bind(fd.get(), reinterpret_cast<sockaddr*>(&address), sizeof address) < 0) {
    return sys_error("bind", endpoint.interface, errno);
  }
  return RawCanWriter(std::move(fd), endpoint.request_id);
}

Expected<std::monostate, RawError> RawCanWriter::write_frame(ByteView data) {
  can_frame frame{};
  frame.can_id = request_id_;
  frame.can_dlc = static_cast<std::uint8_t>(data.size() > CAN_MAX_DLEN ? CAN_MAX_DLEN : data.size());
  std::memcpy(frame.data, data.data(), frame.can_dlc);
  return write_all(fd_.get(), ByteView(reinterpret_cast<const std::uint8_t*>(&frame), sizeof frame), "raw can writer");
}

}  // namespace ldoem::conformance
