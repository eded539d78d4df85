#include "ldoem/io/tcp.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>

namespace ldoem::io {
namespace {

std::string endpoint_text(std::string_view address, std::uint16_t port) {
  return std::string(address) + ":" + std::to_string(port);
}

IoResult<sockaddr_in> ipv4_address(std::string_view address, std::uint16_t port) {
  sockaddr_in result{};
  result.sin_family = AF_INET;
  result.sin_port = htons(port);
  const std::string text(address);
  if (::inet_pton(AF_INET, text.c_str(), &result.sin_addr) != 1) {
    return io_failure(IoError{"inet_pton", text, EINVAL, "not an IPv4 address"});
  }
  return result;
}

std::string text_of(const sockaddr_in& address) {
  std::array<char, INET_ADDRSTRLEN> text{};
  if (::inet_ntop(AF_INET, &address.sin_addr, text.data(), text.size()) == nullptr) {
    return "?";
  }
  return endpoint_text(text.data(), ntohs(address.sin_port));
}

}  // namespace

IoResult<TcpConnection> TcpConnection::connect(std::string_view address, std::uint16_t port) {
  const std::string where = endpoint_text(address, port);
  auto target = ipv4_address(address, port);
  if (!target) {
    return io_failure(target.error());
  }
  base::UniqueFd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!fd.valid()) {
    return io_failure(last_system_error("socket", where));
  }
  while (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&*target), sizeof *target) != 0) {
    if (errno != EINTR) {
      return io_failure(last_system_error("connect", where));
    }
  }
  const int flags = ::fcntl(fd.get(), F_GETFL);
  if (flags < 0 || ::fcntl(fd.get(), F_SETFL, flags | O_NONBLOCK) != 0) {
    return io_failure(last_system_error("fcntl O_NONBLOCK", where));
  }
  // Telegrams are small request/reply exchanges: Nagle would only add latency.
  const int on = 1;
  if (::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &on, sizeof on) != 0) {
    return io_failure(last_system_error("setsockopt TCP_NODELAY", where));
  }
  return TcpConnection(std::move(fd), where);
}

bool TcpConnection::peer_gone() const {
  std::uint8_t byte = 0;
  const ssize_t count = ::recv(fd_.get(), &byte, 1, MSG_PEEK | MSG_DONTWAIT);
  return count == 0 || (count < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
}

IoStatus TcpConnection::reset_on_close() {
  const linger abortive{1, 0};
  if (::setsockopt(fd_.get(), SOL_SOCKET, SO_LINGER, &abortive, sizeof abortive) != 0) {
    return io_failure(last_system_error("setsockopt SO_LINGER", peer_));
  }
  return Done{};
}

IoResult<Received> TcpConnection::receive(std::size_t max_bytes) {
  Received received;
  received.bytes.resize(max_bytes);
  for (;;) {
    const ssize_t got = ::recv(fd_.get(), received.bytes.data(), max_bytes, 0);
    if (got > 0) {
      received.bytes.resize(static_cast<std::size_t>(got));
      return received;
    }
    received.bytes.clear();
    if (got == 0) {
      received.peer_closed = max_bytes > 0;
      return received;
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return received;
    }
    return io_failure(last_system_error("recv", peer_));
  }
}

IoResult<std::size_t> TcpConnection::send(protocol::ByteView bytes) {
  for (;;) {
    const ssize_t sent = ::send(fd_.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (sent >= 0) {
      return static_cast<std::size_t>(sent);
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return std::size_t{0};
    }
    return io_failure(last_system_error("send", peer_));
  }
}

IoResult<TcpListener> TcpListener::listen(std::uint16_t port, std::string_view address,
                                          int backlog) {
  const std::string where = endpoint_text(address, port);
  auto local = ipv4_address(address, port);
  if (!local) {
    return io_failure(local.error());
  }
  base::UniqueFd fd(::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  if (!fd.valid()) {
    return io_failure(last_system_error("socket", where));
  }
  // A restarted daemon must get its port back while old connections sit in TIME_WAIT.
  const int on = 1;
  if (::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) != 0) {
    return io_failure(last_system_error("setsockopt SO_REUSEADDR", where));
  }
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&*local), sizeof *local) != 0) {
    return io_failure(last_system_error("bind", where));
  }
  if (port == 0) {
    // A port the kernel picked is given back when the socket stops listening (stop_listening):
    // a second socket binds it by number while the first still holds it (both SO_REUSEADDR,
    // neither listening), so the port is never free in between.
    sockaddr_in picked{};
    socklen_t picked_length = sizeof picked;
    if (::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&picked), &picked_length) != 0) {
      return io_failure(last_system_error("getsockname", where));
    }
    base::UniqueFd by_number(::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!by_number.valid()) {
      return io_failure(last_system_error("socket", where));
    }
    if (::setsockopt(by_number.get(), SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) != 0) {
      return io_failure(last_system_error("setsockopt SO_REUSEADDR", where));
    }
    if (::bind(by_number.get(), reinterpret_cast<const sockaddr*>(&picked), sizeof picked) != 0) {
      return io_failure(last_system_error("bind", endpoint_text(address, ntohs(picked.sin_port))));
    }
    fd = std::move(by_number);
  }
  if (::listen(fd.get(), backlog) != 0) {
    return io_failure(last_system_error("listen", where));
  }
  sockaddr_in bound{};
  socklen_t length = sizeof bound;
  if (::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&bound), &length) != 0) {
    return io_failure(last_system_error("getsockname", where));
  }
  return TcpListener(std::move(fd), std::string(address), ntohs(bound.sin_port), backlog);
}

IoResult<std::optional<TcpConnection>> TcpListener::accept() {
  for (;;) {
    sockaddr_in peer{};
    socklen_t length = sizeof peer;
    base::UniqueFd fd(::accept4(fd_.get(), reinterpret_cast<sockaddr*>(&peer), &length,
                          SOCK_NONBLOCK | SOCK_CLOEXEC));
    if (fd.valid()) {
      const int on = 1;
      if (::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &on, sizeof on) != 0) {
        return io_failure(last_system_error("setsockopt TCP_NODELAY", text_of(peer)));
      }
      if (::setsockopt(fd.get(), SOL_SOCKET, SO_SNDBUF, &kTcpSendBufferBytes, sizeof kTcpSendBufferBytes) != 0) {
        return io_failure(last_system_error("setsockopt SO_SNDBUF", text_of(peer)));
      }
      return std::optional<TcpConnection>(TcpConnection(std::move(fd), text_of(peer)));
    }
    // A client that gave up between SYN and accept is not our error: try the next one.
    if (errno == EINTR || errno == ECONNABORTED || errno == EPROTO) {
      continue;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return std::optional<TcpConnection>{};
    }
    return io_failure(last_system_error("accept4", endpoint_text(address_, port_)));
  }
}

IoStatus TcpListener::stop_listening() {
  if (::shutdown(fd_.get(), SHUT_RD) != 0) {
    return io_failure(last_system_error("shutdown", endpoint_text(address_, port_)));
  }
  // A bound socket that does not listen lets any other SO_REUSEADDR socket bind and listen on
  // its port; without the flag it does not, until listen_again().
  const int off = 0;
  if (::setsockopt(fd_.get(), SOL_SOCKET, SO_REUSEADDR, &off, sizeof off) != 0) {
    return io_failure(last_system_error("setsockopt SO_REUSEADDR", endpoint_text(address_, port_)));
  }
  return Done{};
}

IoStatus TcpListener::listen_again() {
  const int on = 1;  // connections of before may sit in TIME_WAIT on the port
  if (::setsockopt(fd_.get(), SOL_SOCKET, SO_REUSEADDR, &on, sizeof on) != 0) {
    return io_failure(last_system_error("setsockopt SO_REUSEADDR", endpoint_text(address_, port_)));
  }
  if (::listen(fd_.get(), backlog_) != 0) {
    return io_failure(last_system_error("listen", endpoint_text(address_, port_)));
  }
  return Done{};
}

}  // namespace ldoem::io
