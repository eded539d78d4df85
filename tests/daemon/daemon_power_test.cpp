// D11 faults as a host sees them, on TCP and serial (docs/decisions-local.md L-faults-5, L-faults-6):
// a switched-off device is silent (no FIN, no completed connection, no serial byte), at power-on
// its old connections are reset and it boots before it serves; tcp_reset is a RST; query-status
// says OFF/BOOTING; a TRANS_MEASURE with a stalled motor is refused. Host-only (TCP, a pty, a
// UNIX socket). "Nothing within a bounded wait" and device time judge; no wall-clock window.
#include <gtest/gtest.h>
#include <unistd.h>

#include "host_link.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/test_support/raw_tty.hpp"
#include "power_test_support.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

// A host on the serial pty: one request, the reply's payload as text or "(nothing)" after `limit`.
struct SerialHost {
  int fd = -1;
  explicit SerialHost(const std::string& path) : fd(test_support::open_raw(path)) {}
  ~SerialHost() {
    if (fd >= 0) ::close(fd);
  }
  SerialHost(const SerialHost&) = delete;
  SerialHost& operator=(const SerialHost&) = delete;

  std::string ask(std::string_view request, std::chrono::milliseconds limit = 5s) {
    const Bytes bytes = protocol::encode_serial_request(telegram(request));
    if (::write(fd, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) return "(write failed)";
    protocol::SerialReplyReassembler reassembler;
    const auto deadline = std::chrono::steady_clock::now() + limit;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0 || !wait_readable(fd, left)) return "(nothing)";
      std::uint8_t buffer[512];
      const ssize_t count = ::read(fd, buffer, sizeof buffer);
      if (count <= 0) return "(read failed)";
      for (const auto& event : reassembler.feed(protocol::ByteView(buffer, static_cast<std::size_t>(count)))) {
        if (const auto* reply = std::get_if<protocol::Telegram>(&event)) return protocol::format_telegram(reply->payload);
      }
    }
  }
};

std::string tcp_ask(TcpHost& host, std::string_view request, std::chrono::milliseconds limit = 10s) {
  host.send(telegram(request));
  const auto payload = host.next_payload(limit);
  return payload ? protocol::format_telegram(*payload) : std::string("(nothing)");
}

std::vector<std::string> tcp_and_serial(const TempDir& dir) {
  return {"--no-can", "--tcp", "tcp:127.0.0.1:0", "--serial", "serial:pty:" + dir.path("serial")};
}

// While off: the established connection hears nothing, not even a FIN; a new connection is
// refused; serial answers nothing; query-status shows no state from before the cut.
TEST(DaemonPower, WhileOff_TcpGetsNoByteNoFin_ConnectIsRefused_SerialSilent_StatusSaysOff) {
  TempDir links;
  PowerDaemon d(minimal_scene_text(), tcp_and_serial(links), false);  // real time: off for 10 min
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  SerialHost serial(links.path("serial"));
  ASSERT_GE(serial.fd, 0);
  EXPECT_EQ(tcp_ask(*host, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  ASSERT_EQ(d.status()["head_hz"], 10);
  ASSERT_TRUE(d.power_cycle(600));
  host->send(telegram("GET_STATUS"));
  EXPECT_EQ(next_on_tcp(host->fd(), 1s), "nothing");
  EXPECT_EQ(try_connect(d.process->tcp_port()), "refused");
  EXPECT_EQ(serial.ask("GET_STATUS", 1s), "(nothing)");
  const json status = d.status();
  EXPECT_EQ(status["powered"], false) << status.dump();
  EXPECT_EQ(status["state"], "OFF") << status.dump();
  EXPECT_EQ(status["head_hz"], 0) << status.dump();
  EXPECT_FALSE(status.contains("status_byte")) << status.dump();
}

// At power-on the old connection is reset (RST); while the device boots (60 s here) a new
// connection is refused and serial stays silent; query-status says BOOTING.
TEST(DaemonPower, AtPowerOn_OldTcpConnectionIsReset_WhileBootingConnectRefusedSerialSilent) {
  TempDir links;
  PowerDaemon d(scene_with_scanner("boot_s: 60"), tcp_and_serial(links), false);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  SerialHost serial(links.path("serial"));
  ASSERT_GE(serial.fd, 0);
  EXPECT_EQ(tcp_ask(*host, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  ASSERT_TRUE(d.power_cycle(0.2));
  ASSERT_TRUE(d.control->wait_event("POWER_ON", 10s));
  EXPECT_EQ(next_on_tcp(host->fd(), 5s), "RST");
  EXPECT_EQ(try_connect(d.process->tcp_port()), "refused");
  EXPECT_EQ(serial.ask("GET_STATUS", 1s), "(nothing)");
  const json status = d.status();  // after the attempts: they were all made while booting
  EXPECT_EQ(status["state"], "BOOTING") << status.dump();
  EXPECT_EQ(status["powered"], true) << status.dump();
  EXPECT_EQ(status["head_hz"], 0) << status.dump();
  EXPECT_FALSE(status.contains("status_byte")) << status.dump();
}

// The whole cycle in device time: POWER_ON off_s after POWER_OFF, BOOTED boot_s later; then TCP
// and serial answer in the D4 power-up state.
TEST(DaemonPower, PowerCycle_ServesAgainBootSecondsAfterPowerOn_InThePowerUpState) {
  TempDir links;
  PowerDaemon d(scene_with_scanner("boot_s: 2.5"), tcp_and_serial(links), true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  EXPECT_EQ(tcp_ask(*host, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  ASSERT_TRUE(d.power_cycle(1.5));
  const auto off = d.control->wait_event("POWER_OFF", 10s);
  const auto on = d.control->wait_event("POWER_ON", 10s);
  const auto booted = d.control->wait_event("BOOTED", 10s);
  ASSERT_TRUE(off && on && booted);
  EXPECT_NEAR(event_seconds(*on) - event_seconds(*off), 1.5, 1e-6);
  EXPECT_NEAR(event_seconds(*booted) - event_seconds(*on), 2.5, 1e-6);
  EXPECT_EQ((*on)["data"]["boot_s"], 2.5);
  EXPECT_EQ(next_on_tcp(host->fd(), 5s), "RST");
  auto again = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(again);
  EXPECT_EQ(tcp_ask(*again, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  SerialHost serial(links.path("serial"));
  ASSERT_GE(serial.fd, 0);
  EXPECT_EQ(serial.ask("GET_STATUS"), "GET_STATUS reply 0000 0001");
  const json status = d.status();
  EXPECT_EQ(status["state"], "IDLE") << status.dump();
  EXPECT_EQ(status["status_byte"], 1) << status.dump();
}

TEST(DaemonPower, TcpReset_IsARstNotAFin) {
  PowerDaemon d(minimal_scene_text() + "faults:\n  - {kind: tcp_reset, on: {service: GET_SIGNAL, nth: 1}}\n",
                {"--no-can", "--tcp", "tcp:127.0.0.1:0"}, true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  host->send(telegram("GET_SIGNAL"));
  EXPECT_EQ(next_on_tcp(host->fd(), 5s), "RST");
}

// L-faults-6: the stall comes with the TRANS_MEASURE itself (its trigger), so the request meets
// a stalled motor within the revolution before ERROR, whatever the machine's speed.
void transmeasure_with_a_stalled_motor_is_refused(const std::function<std::string(std::string_view)>& ask) {
  EXPECT_EQ(ask("TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0002");
  EXPECT_EQ(ask("TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003");
  EXPECT_EQ(ask("TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003");  // the stall's revolution or ERROR
  EXPECT_EQ(ask("DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(ask("TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 00b4");  // not cleared: fails at once
}

const std::string kStallOnMeasure =
    minimal_scene_text() + "faults:\n  - {kind: motor_stall, on: {service: TRANS_MEASURE, nth: 1}}\n";

TEST(DaemonPower, TransMeasureWithAStalledMotor_IsRefusedReasonThree_Tcp) {
  PowerDaemon d(kStallOnMeasure, {"--no-can", "--tcp", "tcp:127.0.0.1:0"}, true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  auto host = TcpHost::connect(d.process->tcp_port());
  ASSERT_TRUE(host);
  transmeasure_with_a_stalled_motor_is_refused([&](std::string_view request) { return tcp_ask(*host, request); });
}

TEST(DaemonPower, TransMeasureWithAStalledMotor_IsRefusedReasonThree_Serial) {
  TempDir links;
  PowerDaemon d(kStallOnMeasure, {"--no-can", "--serial", "serial:pty:" + links.path("serial")}, true);
  ASSERT_TRUE(d.ready()) << d.diagnostics();
  SerialHost serial(links.path("serial"));
  ASSERT_GE(serial.fd, 0);
  transmeasure_with_a_stalled_motor_is_refused([&](std::string_view request) { return serial.ask(request, 10s); });
}

}  // namespace
}  // namespace ldoem::daemon::test
