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

  // Makes closing this connection abortive (SO_LINGER {1, 0}): the peer gets a RST, not a FIN,
  // and nothing still queued is sent. For connections a device "forgets" (D11 tcp_reset, a
  // power cycle: docs/decisions-local.md L-faults-5).
  IoStatus reset_on_close();

  int fd() const { return fd_.get(); }
  const std::string& peer() const { return peer_; }  // "127.0.0.1:40412"

 private:
  base::UniqueFd fd_;
  std::string peer_;
};

// The send buffer of an accepted connection (the kernel doubles it: 64 KiB in use). Left to
// itself, Linux grows it up to net.ipv4.tcp_wmem's maximum (4 MiB, more on loopback's 64 KiB
// segments), which behind a host that stopped reading is some 1 800 profiles of 2.2 KiB: three
// minutes at 10 Hz of stale revolutions the host would still get, a queue D10 forbids
// (decisions-local.md L-time-2). 64 KiB still carries 64 KiB per round trip (64 MB/s at 1 ms).
inline constexpr int kTcpSendBufferBytes = 32 * 1024;

class TcpListener {
 public:
  // socket + SO_REUSEADDR + bind + listen. Port 0 picks a free port (see port()); the socket is
  // then bound to that port by number, so that it keeps it across stop_listening(). The backlog
  // defaults to the system's largest (SOMAXCONN; the kernel caps it at net.core.somaxconn):
  // with 16, a connect flood overflowed it and new hosts waited 1 s for a SYN retry (issue 27).
  static IoResult<TcpListener> listen(std::uint16_t port,
                                      std::string_view address = kLoopbackAddress,
                                      int backlog = SOMAXCONN);

  // The next pending connection (TCP_NODELAY, SO_SNDBUF kTcpSendBufferBytes), or nothing when
  // none is waiting.
  IoResult<std::optional<TcpConnection>> accept();

  // Stops listening but keeps the port bound (Linux: shutdown(SHUT_RD) of a listening socket
  // returns it to CLOSE): a connect() to it is refused by the kernel, connections not accepted
  // yet are reset, and no other socket can bind the port meanwhile (SO_REUSEADDR is off until
  // listen_again(), which resumes).
  IoStatus stop_listening();
  IoStatus listen_again();

  int fd() const { return fd_.get(); }
  std::uint16_t port() const { return port_; }
  const std::string& address() const { return address_; }

 private:
  TcpListener(base::UniqueFd fd, std::string address, std::uint16_t port, int backlog)
      : fd_(std::move(fd)), address_(std::move(address)), port_(port), backlog_(backlog) {}

  base::UniqueFd fd_;
  std::string address_;
  std::uint16_t port_ = 0;
  int backlog_ = 16;
};

}  // namespace ldoem::io
