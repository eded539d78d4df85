#include "isotp_host.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>

#include "host_link.hpp"

namespace ldoem::daemon::test {

using namespace std::chrono_literals;

IsoTpHost::IsoTpHost(CanIdPair ids, std::string_view interface_name)
    : channel_(IsoTpChannelConfig{CanIdPair{ids.response_id, ids.request_id}}) {
  auto socket = io::CanRawSocket::open(interface_name, std::vector<io::CanIdFilter>{io::exact_standard_id(ids.response_id)});
  EXPECT_TRUE(socket) << socket.error().message();
  if (!socket) return;
  // With BS 0 (D1) the LD sends a whole profile back to back: ~170 frames for the D4 table. Each
  // queued frame costs about 1 KiB of receive buffer, so the 208 KiB default can overflow while
  // this process is descheduled (UML has one CPU), and a lost frame loses the telegram. Hosts
  // that keep BS 0 need a bigger buffer; as root (in UML) we may force one, as the driver does.
  const int receive_buffer_bytes = 4 << 20;
  if (::setsockopt(socket->fd(), SOL_SOCKET, SO_RCVBUFFORCE, &receive_buffer_bytes, sizeof receive_buffer_bytes) != 0) {
    (void)::setsockopt(socket->fd(), SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
  }
  socket_.emplace(std::move(*socket));
}

std::optional<protocol::Bytes> IsoTpHost::exchange(const protocol::Bytes& request, std::chrono::milliseconds limit) {
  send(request);
  return next(limit);
}

void IsoTpHost::send(const protocol::Bytes& request) { transmit(channel_.send(elapsed(), request).frames); }

std::optional<protocol::Bytes> IsoTpHost::next(std::chrono::milliseconds limit) {
  if (!socket_) return std::nullopt;
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    if (!wait_readable(socket_->fd(), 20ms)) {
      transmit(channel_.poll(elapsed()).frames);  // our own consecutive frames and timeouts
      continue;
    }
    for (;;) {
      auto frame = socket_->receive();
      if (!frame || !frame->has_value()) break;
      auto out = channel_.on_frame(elapsed(), **frame);
      transmit(out.frames);  // our flow control
      if (!out.telegrams.empty()) return out.telegrams.front();
    }
  }
  return std::nullopt;
}

std::vector<protocol::Bytes> IsoTpHost::drain(std::chrono::milliseconds span) {
  std::vector<protocol::Bytes> seen;
  const auto until = std::chrono::steady_clock::now() + span;
  while (std::chrono::steady_clock::now() < until) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    if (auto telegram = next(std::max(left, 1ms))) seen.push_back(std::move(*telegram));
  }
  return seen;
}

void IsoTpHost::transmit(const std::vector<protocol::CanFrame>& frames) {
  for (const auto& frame : frames) {
    auto sent = socket_->send(frame);
    EXPECT_TRUE(sent) << sent.error().message();
  }
}

}  // namespace ldoem::daemon::test
