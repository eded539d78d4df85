// ldoem-emud --record and the end of a TCP connection (docs/capture.md, issue 24 item 10): a
// host that closes leaves a FIN both ways in the recording; a connection the device resets (a
// tcp_reset fault) leaves one RST from the device. Read back with ldoem's capture reader.
#include <gtest/gtest.h>

#include <thread>
#include <variant>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/capture/capture_packets.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

struct Flags {
  int fin_to_device = 0;
  int fin_to_host = 0;
  int rst_to_host = 0;
  int rst_to_device = 0;
};

Flags tcp_flags(const std::filesystem::path& path) {
  Flags flags;
  const auto packets = capture::read_capture_packets(path);
  if (!packets) return flags;
  for (const auto& packet : packets->packets) {
    const auto* segment = std::get_if<capture::TcpSegment>(&packet.payload);
    if (segment == nullptr) continue;
    const bool to_device = segment->destination_port == 49152;
    if ((segment->flags & capture::kTcpFin) != 0) ++(to_device ? flags.fin_to_device : flags.fin_to_host);
    if ((segment->flags & capture::kTcpRst) != 0) ++(to_device ? flags.rst_to_device : flags.rst_to_host);
  }
  return flags;
}

// The close reaches the recording through the daemon's loop: wait for it, bounded.
Flags wait_for_end(const std::filesystem::path& path) {
  Flags flags;
  for (int i = 0; i < 100; ++i) {
    flags = tcp_flags(path);
    if (flags.fin_to_host + flags.rst_to_host > 0) break;
    std::this_thread::sleep_for(50ms);
  }
  return flags;
}

std::optional<DaemonProcess> start(const TempDir& dir, const std::string& scene_text) {
  return DaemonProcess::start({"--scene", dir.write("scene.yaml", scene_text), "--no-can", "--tcp", "tcp:127.0.0.1:0",
                               "--no-flash", "--virtual-time", "--record", dir.path("r.pcapng")});
}

TEST(DaemonRecording, HostCloses_RecordsFinBothWays) {
  TempDir dir;
  auto daemon = start(dir, minimal_scene_text());
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  {
    auto host = TcpHost::connect(daemon->tcp_port());
    ASSERT_TRUE(host);
    host->send(telegram("GET_STATUS"));
    ASSERT_TRUE(host->next_payload(5s));
  }  // closed here
  const Flags flags = wait_for_end(dir.path("r.pcapng"));
  EXPECT_EQ(flags.fin_to_device, 1);
  EXPECT_EQ(flags.fin_to_host, 1);
  EXPECT_EQ(flags.rst_to_host + flags.rst_to_device, 0);
}

TEST(DaemonRecording, TcpResetFault_RecordsRstFromTheDevice) {
  TempDir dir;
  auto daemon = start(dir, minimal_scene_text() + "faults:\n  - kind: tcp_reset\n    on: {service: GET_SIGNAL, nth: 1}\n");
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  auto host = TcpHost::connect(daemon->tcp_port());
  ASSERT_TRUE(host);
  host->send(telegram("GET_SIGNAL"));
  ASSERT_TRUE(host->closed_by_peer(5s));
  const Flags flags = wait_for_end(dir.path("r.pcapng"));
  EXPECT_EQ(flags.rst_to_host, 1);
  EXPECT_EQ(flags.fin_to_host + flags.fin_to_device + flags.rst_to_device, 0);
}

}  // namespace
}  // namespace ldoem::daemon::test
