#include "host_link.hpp"

#include <poll.h>

#include <cstdio>
#include <sstream>

namespace ldoem::daemon::test {

Bytes hex(std::string_view text) {
  Bytes bytes;
  std::istringstream in{std::string(text)};
  std::string token;
  while (in >> token) bytes.push_back(static_cast<std::uint8_t>(std::stoul(token, nullptr, 16)));
  return bytes;
}

std::string to_hex(protocol::ByteView bytes) {
  std::string text;
  char digits[4];
  for (const std::uint8_t byte : bytes) {
    std::snprintf(digits, sizeof digits, "%02X", byte);
    if (!text.empty()) text += ' ';
    text += digits;
  }
  return text;
}

Bytes telegram(std::string_view text) {
  auto bytes = protocol::parse_telegram(text);
  EXPECT_TRUE(bytes.has_value()) << text;
  return bytes ? *bytes : Bytes{};
}

std::optional<std::uint16_t> distance_at_angle_zero(const protocol::Profile& profile) {
  for (const auto& sector : profile.sectors) {
    for (std::size_t i = 0; i < sector.points.size(); ++i) {
      if ((sector.start_dir_ticks + i * sector.dir_step_ticks) % 5760 == 0) return sector.points[i].distance_q8_m;
    }
  }
  return std::nullopt;
}

bool wait_readable(int fd, std::chrono::milliseconds limit) {
  pollfd descriptor{fd, POLLIN, 0};
  return ::poll(&descriptor, 1, static_cast<int>(limit.count())) > 0;
}

std::optional<TcpHost> TcpHost::connect(std::uint16_t port) {
  auto connection = io::TcpConnection::connect("127.0.0.1", port);
  EXPECT_TRUE(connection) << connection.error().message();
  if (!connection) return std::nullopt;
  return TcpHost(std::move(*connection));
}

void TcpHost::send_raw(protocol::ByteView bytes) {
  while (!bytes.empty()) {
    auto sent = connection_.send(bytes);
    ASSERT_TRUE(sent) << sent.error().message();
    bytes = bytes.subspan(*sent);
    if (!bytes.empty()) {
      pollfd descriptor{connection_.fd(), POLLOUT, 0};
      ::poll(&descriptor, 1, 100);
    }
  }
}

bool TcpHost::fill(std::chrono::milliseconds limit) {
  if (closed_ || !wait_readable(connection_.fd(), limit)) return false;
  auto received = connection_.receive();
  if (!received) {
    closed_ = true;
    return false;
  }
  buffer_.insert(buffer_.end(), received->bytes.begin(), received->bytes.end());
  if (received->peer_closed) closed_ = true;
  return !received->bytes.empty();
}

std::optional<Bytes> TcpHost::next_frame(std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    if (buffer_.size() >= protocol::kTcpHeaderSize) {
      const std::size_t size = protocol::tcp_frame_size(protocol::read_u32_be(buffer_, 4));
      if (buffer_.size() >= size) {
        Bytes frame(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(size));
        buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(size));
        return frame;
      }
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || !fill(left)) {
      if (std::chrono::steady_clock::now() >= deadline || closed_) return std::nullopt;
    }
  }
}

std::optional<Bytes> TcpHost::next_payload(std::chrono::milliseconds limit) {
  auto frame = next_frame(limit);
  if (!frame) return std::nullopt;
  protocol::TcpDeframer deframer;
  const auto events = deframer.feed(*frame);
  EXPECT_EQ(events.size(), 1u) << to_hex(*frame);
  if (events.size() != 1 || !std::holds_alternative<protocol::Telegram>(events[0])) return std::nullopt;
  return std::get<protocol::Telegram>(events[0]).payload;
}

bool TcpHost::closed_by_peer(std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!closed_ && std::chrono::steady_clock::now() < deadline) {
    buffer_.clear();  // drain whatever was queued before the close
    fill(std::chrono::milliseconds(100));
  }
  return closed_;
}

}  // namespace ldoem::daemon::test
