// TCP listener and connections for the emulator's Ethernet interface (spec 4.1, port 49152) and
// the hub. IPv4, non-blocking; loopback unless the caller names another address.
#pragma once

#include <sys/socket.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/io/byte_stream.hpp"
#include "ldoem/io/io_error.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {

inline constexpr std::string_view kLoopbackAddress = "127.0.0.1";

class TcpConnection {
 public:
  // Connects (blocking, then switches to non-blocking): for tests and simple clients.
  static IoResult<TcpConnection> connect(std::string_view address, std::uint16_t port);
  // Takes over an accepted, already non-blocking socket.
  TcpConnection(base::UniqueFd fd, std::string peer) : fd_(std::move(fd)), peer_(std::move(peer)) {}

  IoResult<Received> receive(std::size_t max_bytes = 65536);
  // How many leading bytes the kernel took (0 when its buffer is full). Never raises SIGPIPE:
  // a vanished peer is an EPIPE error value.
  IoResult<std::size_t> send(protocol::ByteView bytes);

  // True when the peer has gone and left nothing unread: EOF, or a reset waiting to be read.
  // A peek: nothing is consumed.
  bool peer_gone() const;

  int fd() const { return fd_.get(); }
  const std::string& peer() const { return peer_; }  // "127.0.0.1:40412"

 private:
  base::UniqueFd fd_;
  std::string peer_;
};

class TcpListener {
 public:
  // socket + SO_REUSEADDR + bind + listen. Port 0 picks a free port (see port()). The backlog
  // defaults to the system's largest (SOMAXCONN; the kernel caps it at net.core.somaxconn):
  // with 16, a connect flood overflowed it and new hosts waited 1 s for a SYN retry (issue 27).
  static IoResult<TcpListener> listen(std::uint16_t port,
                                      std::string_view address = kLoopbackAddress,
                                      int backlog = SOMAXCONN);

  // The next pending connection, or nothing when none is waiting.
  IoResult<std::optional<TcpConnection>> accept();

  int fd() const { return fd_.get(); }
  std::uint16_t port() const { return port_; }
  const std::string& address() const { return address_; }

 private:
  TcpListener(base::UniqueFd fd, std::string address, std::uint16_t port)
      : fd_(std::move(fd)), address_(std::move(address)), port_(port) {}

  base::UniqueFd fd_;
  std::string address_;
  std::uint16_t port_ = 0;
};

}  // namespace ldoem::io
