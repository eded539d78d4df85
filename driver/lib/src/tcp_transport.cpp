#include "ldoem/driver/tcp_transport.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <variant>

#include "fd_util.hpp"
#include "stream_io.hpp"

namespace ldoem::driver {
namespace {

constexpr std::size_t kTcpReadChunkBytes = 8192;

struct AddrInfoDeleter {
  void operator()(addrinfo* list) const { freeaddrinfo(list); }
};

Expected<base::UniqueFd, DriverError> connect_one(const addrinfo& address, Deadline deadline,
                                                    const std::string& object) {
  base::UniqueFd fd(::socket(address.ai_family, address.ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC,
                               address.ai_protocol));
  if (!fd.valid()) {
    return fail(system_error("socket", object, errno));
  }
  if (::connect(fd.get(), address.ai_addr, address.ai_addrlen) != 0) {
    if (errno != EINPROGRESS) {
      return fail(system_error("connect", object, errno));
    }
    auto waited = detail::wait_for(fd.get(), POLLOUT, deadline, "connect", object);
    if (!waited) {
      return fail(waited.error());
    }
    if (*waited == detail::WaitOutcome::deadline_passed) {
      return fail(make_error(ErrorKind::timeout, "connect", object, "no connection within the timeout"));
    }
    int socket_error = 0;
    socklen_t length = sizeof socket_error;
    if (::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &socket_error, &length) != 0) {
      return fail(system_error("getsockopt SO_ERROR", object, errno));
    }
    if (socket_error != 0) {
      return fail(system_error("connect", object, socket_error));
    }
  }
  const int one = 1;
  if (::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one) != 0) {
    return fail(system_error("setsockopt TCP_NODELAY", object, errno));
  }
  return fd;
}

}  // namespace

Expected<std::unique_ptr<TcpTransport>, DriverError> TcpTransport::connect(
    const TcpEndpoint& endpoint, std::chrono::milliseconds connect_timeout) {
  const std::string object = format_endpoint(endpoint);
  const Deadline deadline = Clock::now() + connect_timeout;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* raw_list = nullptr;
  const std::string port = std::to_string(endpoint.port);
  const int resolved = ::getaddrinfo(endpoint.host.c_str(), port.c_str(), &hints, &raw_list);
  if (resolved != 0) {
    return fail(make_error(ErrorKind::system, "resolve", object, gai_strerror(resolved)));
  }
  std::unique_ptr<addrinfo, AddrInfoDeleter> list(raw_list);
  DriverError last = make_error(ErrorKind::system, "connect", object, "no address");
  for (const addrinfo* address = list.get(); address != nullptr; address = address->ai_next) {
    auto fd = connect_one(*address, deadline, object);
    if (fd) {
      return std::unique_ptr<TcpTransport>(new TcpTransport(fd->release(), object));
    }
    last = fd.error();
  }
  return fail(last);
}

Status TcpTransport::send(ByteView payload, Deadline deadline) {
  // The whole frame in one buffer and one send() call: a frame is never split by us (D10).
  return send_framed(protocol::encode_tcp_frame(payload), deadline, detail::kTcpStream);
}

Expected<Bytes, DriverError> TcpTransport::receive(Deadline deadline) {
  return detail::receive_telegram<kTcpReadChunkBytes>(fd_.get(), deadline, detail::kTcpStream, name_, deframer_, received_,
                                                   counters_, kTcpFrameGap);
}

TransportCounters TcpTransport::counters() const {
  return counters_with(deframer_.dropped_frames(), deframer_.skipped_bytes());
}

}  // namespace ldoem::driver
