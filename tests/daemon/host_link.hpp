// A test host on TCP or on the serial pty: sends requests, reads telegrams with a time limit.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <deque>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/io/tcp.hpp"
#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "ldoem/protocol/text.hpp"

namespace ldoem::daemon::test {

using protocol::Bytes;

Bytes hex(std::string_view text);          // "02 55 53 50" -> bytes
std::string to_hex(protocol::ByteView bytes);  // bytes -> "02 55 53 50"
Bytes telegram(std::string_view text);     // protocol text form -> payload

// DISTANCE of the point at head angle 0 (+x, D5). D4's sector 0 measures from 225.25 deg
// through 0 to 135 deg, so that point is in the middle of the sector.
std::optional<std::uint16_t> distance_at_angle_zero(const protocol::Profile& profile);

// Waits until `fd` is readable or `limit` passes.
bool wait_readable(int fd, std::chrono::milliseconds limit);

class TcpHost {
 public:
  static std::optional<TcpHost> connect(std::uint16_t port);

  void send_raw(protocol::ByteView bytes);
  void send(protocol::ByteView payload) { send_raw(protocol::encode_tcp_frame(payload)); }
  // The next whole frame as raw bytes (header to checksum), or nothing after `limit`.
  std::optional<Bytes> next_frame(std::chrono::milliseconds limit = std::chrono::seconds(10));
  // The next telegram's payload (framing checked by the deframer).
  std::optional<Bytes> next_payload(std::chrono::milliseconds limit = std::chrono::seconds(10));
  // True when the daemon closed the connection within `limit`.
  bool closed_by_peer(std::chrono::milliseconds limit);
  int fd() const { return connection_.fd(); }

 private:
  explicit TcpHost(io::TcpConnection connection) : connection_(std::move(connection)) {}
  bool fill(std::chrono::milliseconds limit);
  io::TcpConnection connection_;
  Bytes buffer_;
  bool closed_ = false;
};

}  // namespace ldoem::daemon::test
