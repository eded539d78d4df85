// D11 faults as a host sees them, on CAN (docs/decisions-local.md L-faults-5, L-faults-6), on a
// real vcan0 inside User-Mode Linux (label vcan; they FAIL, never skip, without vcan0):
//   scripts/uml/run.sh -- ctest --test-dir build/default -L vcan -R DaemonPowerVcan
// A switched-off or booting device sends no frame at all, not even ISO-TP flow control; it
// serves again boot_s after power-on; a TRANS_MEASURE with a stalled motor is refused.
#include "host_link.hpp"
#include "isotp_host.hpp"
#include "ldoem/io/can_socket.hpp"
#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/test_support/require_vcan.hpp"
#include "power_test_support.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

// The host on CAN_RAW: frames to 0x6C0; whether any frame came on 0x6C1 within a bounded wait.
class RawCanHost {
 public:
  RawCanHost() {
    auto opened = io::CanRawSocket::open("vcan0", std::vector<io::CanIdFilter>{io::exact_standard_id(0x6C1)});
    EXPECT_TRUE(opened) << opened.error().message();
    if (opened) socket_.emplace(std::move(*opened));
  }
  void send(const protocol::Bytes& bytes) {
    ASSERT_TRUE(socket_);
    ASSERT_TRUE(socket_->send(*protocol::make_can_frame(0x6C0, bytes)));
  }
  // The next frame's bytes as hex, or "(nothing)" within `limit`.
  std::string next(std::chrono::milliseconds limit) {
    if (!socket_ || !wait_readable(socket_->fd(), limit)) return "(nothing)";
    auto received = socket_->receive();
    if (!received || !received->has_value()) return "(nothing)";
    return to_hex((**received).payload());
  }

 private:
  std::optional<io::CanRawSocket> socket_;
};

// SET_CONFIG 0010 ... (14 bytes) begins with this first frame: a healthy device answers it with
// flow control `30 ..` at once.
const protocol::Bytes kFirstFrame{0x10, 0x0E, 0x02, 0x01, 0x00, 0x10, 0x00, 0x01};
const protocol::Bytes kGetStatus{0x02, 0x01, 0x02};  // a single frame

TEST(DaemonPowerVcan, WhileOff_NoFrameAtAll_NotEvenFlowControl_StatusSaysOff) {
  LDOEM_REQUIRE_VCAN0();
  PowerDaemon d(minimal_scene_text(), {"--can", "can:vcan0"}, false);  // real time: off for 10 min
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawCanHost host;
  host.send(kGetStatus);
  ASSERT_EQ(host.next(5s), "06 81 02 00 00 00 01");
  ASSERT_TRUE(d.power_cycle(600));
  host.send(kFirstFrame);
  EXPECT_EQ(host.next(1s), "(nothing)");
  host.send(kGetStatus);
  EXPECT_EQ(host.next(1s), "(nothing)");
  const json status = d.status();
  EXPECT_EQ(status["state"], "OFF") << status.dump();
  EXPECT_FALSE(status.contains("status_byte")) << status.dump();
}

TEST(DaemonPowerVcan, WhileBooting_NoFrame_StatusSaysBooting) {
  LDOEM_REQUIRE_VCAN0();
  PowerDaemon d(scene_with_scanner("boot_s: 60"), {"--can", "can:vcan0"}, false);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  RawCanHost host;
  ASSERT_TRUE(d.power_cycle(0.2));
  ASSERT_TRUE(d.control->wait_event("POWER_ON", 10s));
  host.send(kGetStatus);
  EXPECT_EQ(host.next(1s), "(nothing)");
  host.send(kFirstFrame);
  EXPECT_EQ(host.next(1s), "(nothing)");
  EXPECT_EQ(d.status()["state"], "BOOTING");  // after the requests: they were made while booting
}

TEST(DaemonPowerVcan, PowerCycle_ServesAgainBootSecondsAfterPowerOn) {
  LDOEM_REQUIRE_VCAN0();
  PowerDaemon d(scene_with_scanner("boot_s: 2"), {"--can", "can:vcan0"}, true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  IsoTpHost host(CanIdPair{0x6C0, 0x6C1});
  EXPECT_EQ(host.exchange(telegram("TRANS_ROTATE 0000")), std::optional<Bytes>(telegram("TRANS_ROTATE reply 0000 0002")));
  ASSERT_TRUE(d.power_cycle(1));
  const auto on = d.control->wait_event("POWER_ON", 10s);
  const auto booted = d.control->wait_event("BOOTED", 10s);
  ASSERT_TRUE(on && booted);
  EXPECT_NEAR(event_seconds(*booted) - event_seconds(*on), 2.0, 1e-6);
  EXPECT_EQ(host.exchange(telegram("GET_STATUS")), std::optional<Bytes>(telegram("GET_STATUS reply 0000 0001")));
}

TEST(DaemonPowerVcan, TransMeasureWithAStalledMotor_IsRefusedReasonThree) {
  LDOEM_REQUIRE_VCAN0();
  PowerDaemon d(minimal_scene_text() + "faults:\n  - {kind: motor_stall, on: {service: TRANS_MEASURE, nth: 1}}\n",
                {"--can", "can:vcan0"}, true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  IsoTpHost host(CanIdPair{0x6C0, 0x6C1});
  auto ask = [&](std::string_view request) {
    const auto reply = host.exchange(telegram(request));
    return reply ? protocol::format_telegram(*reply) : std::string("(nothing)");
  };
  EXPECT_EQ(ask("TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  EXPECT_EQ(ask("TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003");
  EXPECT_EQ(ask("TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003");
  EXPECT_EQ(ask("DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(ask("TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 00b4");
}

}  // namespace
}  // namespace ldoem::daemon::test
