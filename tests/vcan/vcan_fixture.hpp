// Shared helpers of the vcan tests. They need the vcan0 that scripts/uml/run.sh creates; without
// it they fail with the reason, on purpose (CI must not pass without the UML harness).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <vector>

#include "ldoem/io/can_socket.hpp"
#include "ldoem/io/event_loop.hpp"

namespace ldoem::test {

inline constexpr const char* kVcan = "vcan0";

// Opens a CanRawSocket into `name`, or fails the test with the reason (no vcan0 outside UML).
#define LDOEM_ASSERT_OPEN_CAN(name, ...)                                                        \
  auto name##_opened = ::ldoem::io::CanRawSocket::open(__VA_ARGS__);                          \
  ASSERT_TRUE(name##_opened) << name##_opened.error().message()                               \
                             << " (vcan tests run inside UML: scripts/uml/run.sh -- ctest -L vcan)"; \
  ::ldoem::io::CanRawSocket& name = *name##_opened

// Frames `socket` receives within `limit`, driven by an EventLoop (stops at `count`).
inline std::vector<protocol::CanFrame> receive_frames(io::CanRawSocket& socket, std::size_t count,
                                                      std::chrono::milliseconds limit) {
  std::vector<protocol::CanFrame> frames;
  auto loop = io::EventLoop::create();
  EXPECT_TRUE(loop) << loop.error().message();
  if (!loop) {
    return frames;
  }
  auto watched = (*loop)->watch(socket.fd(), io::Interest::readable, [&](io::Readiness) {
    for (;;) {
      auto frame = socket.receive();
      ASSERT_TRUE(frame) << frame.error().message();
      if (!frame->has_value()) {
        break;
      }
      frames.push_back(**frame);
    }
    if (frames.size() >= count) {
      (*loop)->stop();
    }
  });
  EXPECT_TRUE(watched) << watched.error().message();
  auto ran = (*loop)->run_for(limit);
  EXPECT_TRUE(ran) << ran.error().message();
  return frames;
}

inline protocol::CanFrame frame_of(std::uint32_t id, std::vector<std::uint8_t> bytes) {
  auto frame = protocol::make_can_frame(id, bytes);
  EXPECT_TRUE(frame.has_value());
  return frame.value_or(protocol::CanFrame{});
}

}  // namespace ldoem::test
