// A tiny scripted TCP server on 127.0.0.1 (ephemeral port) for TcpTransport tests: it accepts
// one connection and, per step, reads exactly the expected number of bytes, records them and
// writes the step's reply bytes in one send.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::driver::test {

struct ServerStep {
  std::size_t expect_bytes = 0;  // read this many bytes first (0: read nothing)
  protocol::Bytes reply;         // then send these (empty: send nothing)
};

class ScriptedTcpServer {
 public:
  explicit ScriptedTcpServer(std::vector<ServerStep> steps, bool close_after = false)
      : steps_(std::move(steps)), close_after_(close_after) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0;
    if (listen_fd_ < 0 || ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listen_fd_, 1) != 0) {
      throw std::runtime_error("test server: cannot listen on 127.0.0.1");
    }
    socklen_t length = sizeof address;
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
    port_ = ntohs(address.sin_port);
    thread_ = std::thread([this] { run(); });
  }

  ~ScriptedTcpServer() {
    if (thread_.joinable()) {
      thread_.join();
    }
    ::close(listen_fd_);
  }

  std::uint16_t port() const { return port_; }

  // Everything the client sent, once the script has run (joins the server thread).
  const protocol::Bytes& received() {
    if (thread_.joinable()) {
      thread_.join();
    }
    return received_;
  }

 private:
  static constexpr int kWaitMs = 5000;

  bool read_exactly(int fd, std::size_t count) {
    while (count > 0) {
      pollfd entry{fd, POLLIN, 0};
      if (::poll(&entry, 1, kWaitMs) <= 0) {
        return false;
      }
      std::uint8_t buffer[4096];
      const ssize_t got = ::recv(fd, buffer, std::min(count, sizeof buffer), 0);
      if (got <= 0) {
        return false;
      }
      received_.insert(received_.end(), buffer, buffer + got);
      count -= static_cast<std::size_t>(got);
    }
    return true;
  }

  void run() {
    pollfd entry{listen_fd_, POLLIN, 0};
    if (::poll(&entry, 1, kWaitMs) <= 0) {
      return;
    }
    const int fd = ::accept(listen_fd_, nullptr, nullptr);
    if (fd < 0) {
      return;
    }
    for (const ServerStep& step : steps_) {
      if (!read_exactly(fd, step.expect_bytes)) {
        break;
      }
      if (!step.reply.empty()) {
        (void)::send(fd, step.reply.data(), step.reply.size(), MSG_NOSIGNAL);
      }
    }
    if (!close_after_) {
      // Wait for the client to hang up, so that replies are not cut by our close.
      pollfd client{fd, POLLIN, 0};
      std::uint8_t sink[256];
      while (::poll(&client, 1, kWaitMs) > 0) {
        const ssize_t got = ::recv(fd, sink, sizeof sink, 0);
        if (got <= 0) {
          break;
        }
        received_.insert(received_.end(), sink, sink + got);
      }
    }
    ::close(fd);
  }

  std::vector<ServerStep> steps_;
  bool close_after_;
  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::thread thread_;
  protocol::Bytes received_;
};

}  // namespace ldoem::driver::test
