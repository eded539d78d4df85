// ldoem-emud on vcan0 (D1) against a hostile bus: cangen floods at full rate and malformed
// ISO-TP sequences from cansend. Inside UML only:
//   scripts/uml/run.sh -- ctest --test-dir BUILD -L vcan --output-on-failure
// Without vcan0 these tests FAIL (never skip). LDOEM_FLOOD_SECONDS sets the flood (default 30 s).
#include <signal.h>

#include <thread>

#include "isotp_host.hpp"
#include "ldoem/io/can_interface.hpp"
#include "ldoem/test_support/require_vcan.hpp"
#include "robustness.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

const Bytes kFirmwareName{0x81, 0x01, 'l', 'd', 'o', 'e', 'm', '-', 'e', 'm', 'u', 'd'};  // D3

// The correct request after the abuse: GET_IDENTIFICATION 0011 (its reply does not depend on
// whatever state random frames may have put the LD in) as an ISO-TP exchange. Replies still
// queued from the abuse are read off first, until the bus has been quiet for 500 ms.
::testing::AssertionResult served_correctly() {
  IsoTpHost host(CanIdPair{0x6C0, 0x6C1});
  if (!host.is_open()) return ::testing::AssertionFailure() << "no CAN socket";
  for (int round = 0; round < 40 && !host.drain(500ms).empty(); ++round) {
  }
  const auto reply = host.exchange(telegram("GET_IDENTIFICATION 0011"));
  if (reply != std::optional<Bytes>(kFirmwareName)) {
    return ::testing::AssertionFailure() << "reply " << (reply ? to_hex(*reply) : "(none)");
  }
  return ::testing::AssertionSuccess();
}

std::optional<std::uint64_t> counter(DaemonProcess& daemon, const std::string& name) {
  daemon.signal(SIGUSR1);
  std::this_thread::sleep_for(300ms);
  const std::string text = daemon.stderr_text();
  const auto field = text.rfind(" " + name + "=");
  if (field == std::string::npos) return std::nullopt;
  return std::stoull(text.substr(field + name.size() + 2));
}

TEST(CanRobustness, CangenFloodAtFullRate_DaemonSurvivesAndAnswersAfterwards) {
  LDOEM_REQUIRE_VCAN0();
  HostileRun daemon({"--can", "can:vcan0"});
  ASSERT_TRUE(daemon.ready());
  // Random identifiers as the issue asks, and random frames on our request identifier (the
  // kernel filter lets only those through), data and RTR, ignoring ENOBUFS (-i).
  std::vector<DaemonProcess> floods;
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"vcan0", "-g", "0", "-i", "-I", "r", "-L", "r", "-D", "r"},
        std::vector<std::string>{"vcan0", "-g", "0", "-i", "-I", "6C0", "-L", "r", "-D", "r"},
        std::vector<std::string>{"vcan0", "-g", "0", "-i", "-e", "-I", "r", "-L", "r", "-D", "r"}}) {
    auto flood = DaemonProcess::start_program("cangen", arguments);
    ASSERT_TRUE(flood) << "cangen did not start";
    floods.push_back(std::move(*flood));
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(flood_seconds());
  while (std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(1s);
    ASSERT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
    for (auto& flood : floods) ASSERT_TRUE(flood.alive()) << "cangen stopped: " << flood.stderr_text();
  }
  for (auto& flood : floods) {
    flood.signal(SIGTERM);
    flood.wait();
  }
  EXPECT_TRUE(served_correctly());
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
  EXPECT_GT(counter(*daemon.process, "telegrams_received").value_or(0), 0u);
}

// What the LD puts on its response identifier within `span`.
std::vector<protocol::CanFrame> frames_from_ld(io::CanRawSocket& socket, std::chrono::milliseconds span) {
  std::vector<protocol::CanFrame> frames;
  const auto until = std::chrono::steady_clock::now() + span;
  while (std::chrono::steady_clock::now() < until) {
    if (!wait_readable(socket.fd(), 20ms)) continue;
    while (auto frame = socket.receive()) {
      if (!frame->has_value()) break;
      frames.push_back(**frame);
    }
  }
  return frames;
}

void cansend(const std::string& frame) {
  auto sender = DaemonProcess::start_program("cansend", {"vcan0", frame});
  ASSERT_TRUE(sender);
  EXPECT_EQ(sender->wait(), std::optional<int>(0)) << frame << ": " << sender->stderr_text();
}

TEST(CanRobustness, MalformedIsoTpSequences_AreDroppedAndCounted) {
  LDOEM_REQUIRE_VCAN0();
  HostileRun daemon({"--can", "can:vcan0"});
  ASSERT_TRUE(daemon.ready());
  auto listener = io::CanRawSocket::open("vcan0", std::vector<io::CanIdFilter>{io::exact_standard_id(0x6C1)});
  ASSERT_TRUE(listener) << listener.error().message();

  // D1: a broken segment sequence drops the partial telegram and sends nothing.
  for (const char* frame : {
           "6C0#21AABBCCDDEEFF00",  // consecutive frame without a first frame
           "6C0#05010203",          // single frame claiming 5 bytes, carrying 3 (truncated)
           "6C0#00",                // single frame of length 0
           "6C0#",                  // no data at all
           "6C0#R",                 // remote frame on the request identifier
       }) {
    cansend(frame);
    EXPECT_TRUE(frames_from_ld(*listener, 200ms).empty()) << frame;
  }
  // First frame of a 10-byte GET_CONFIG: our flow control (BS 0, STmin 0) goes out ...
  cansend("6C0#100A02020010AABB");
  const auto flow_control = frames_from_ld(*listener, 300ms);
  ASSERT_EQ(flow_control.size(), 1u);
  EXPECT_EQ(to_hex(flow_control.front().payload()), "30 00 00");
  // ... but a consecutive frame with sequence number 3 instead of 1 breaks it: nothing comes.
  cansend("6C0#23CCDDEEFF");
  EXPECT_TRUE(frames_from_ld(*listener, 300ms).empty());
  // A first frame announcing 4 GiB - 1 bytes (32-bit escape, D1): refused with an overflow
  // flow control (FS 2), nothing allocated.
  cansend("6C0#10000FFFFFFF0102");
  const auto overflow = frames_from_ld(*listener, 300ms);
  ASSERT_EQ(overflow.size(), 1u);
  EXPECT_EQ(overflow.front().payload()[0], 0x32);
  cansend("6C0#1000FFFFFFFF0102");
  EXPECT_EQ(frames_from_ld(*listener, 300ms).size(), 1u);
  // A first frame shorter than a single frame could carry (length 5): not a valid first frame.
  cansend("6C0#1005010203040506");
  cansend("6C0#300000");  // flow control while we send nothing
  EXPECT_TRUE(frames_from_ld(*listener, 300ms).size() <= 1u);  // at most an overflow/ignore answer

  EXPECT_GE(counter(*daemon.process, "isotp_receive_errors").value_or(0), 4u) << daemon.process->stderr_text();
  EXPECT_TRUE(served_correctly());
  EXPECT_TRUE(still_healthy(*daemon.process, daemon.start_rss_kib));
}

}  // namespace
}  // namespace ldoem::daemon::test
