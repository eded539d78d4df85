// The endpoint against can-utils, the reference tools for SocketCAN (design.md convention 1):
// what cansend writes we read, and what we write candump logs with the same bytes.
#include <gtest/gtest.h>

#include <chrono>
#include <regex>

#include "child_process.hpp"
#include "vcan_fixture.hpp"

namespace ldoem::test {
namespace {

using namespace std::chrono_literals;

TEST(CanUtilsInterop, FrameFromCansend_IsReceivedByTheEndpoint) {
  LDOEM_ASSERT_OPEN_CAN(receiver, kVcan);
  ASSERT_EQ(run_program({"cansend", "vcan0", "6C0#0102"}), 0) << "cansend failed (can-utils)";
  const auto frames = receive_frames(receiver, 1, 2s);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], frame_of(0x6C0, {0x01, 0x02}));
}

TEST(CanUtilsInterop, FrameFromTheEndpoint_IsLoggedByCandumpWithTheSameBytes) {
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  auto candump = CapturedProcess::start({"candump", "-n", "1", "-L", "vcan0"});
  ASSERT_TRUE(candump.has_value()) << "cannot start candump (can-utils)";
  const protocol::CanFrame frame = frame_of(0x6C1, {0x00, 0x0A, 0xFF, 0x80, 0x7F});
  // candump is ready only once it has bound its socket, and says nothing when it is: send until
  // it logs one frame and exits (-n 1). Every frame sent is the same, so any one will do.
  const auto end = std::chrono::steady_clock::now() + 5s;
  while (candump->running() && std::chrono::steady_clock::now() < end) {
    ASSERT_TRUE(sender.send(frame));
    candump->collect_output(50ms);
  }
  ASSERT_EQ(candump->wait(1s), 0) << "candump output: " << candump->output();
  // -L log format: "(seconds.micros) interface id#data"
  const std::regex logged(R"(^\(\d+\.\d{6}\) vcan0 6C1#000AFF807F\n$)");
  EXPECT_TRUE(std::regex_match(candump->output(), logged)) << candump->output();
}

}  // namespace
}  // namespace ldoem::test
