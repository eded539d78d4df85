// ldoem-emud on a real SocketCAN vcan0 (D1). Runs inside User-Mode Linux:
//   scripts/uml/run.sh -- ctest --test-dir BUILD -L vcan --output-on-failure
// Without vcan0 these tests FAIL (never skip): CI must not go green without the harness.
#include <signal.h>

#include <functional>
#include <thread>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "isotp_host.hpp"
#include "ldoem/endpoints/isotp_channel.hpp"
#include "ldoem/io/can_interface.hpp"
#include "ldoem/test_support/require_vcan.hpp"
#include "ldoem/io/can_socket.hpp"
#include "ldoem/io/event_loop.hpp"
#include "ldoem/protocol/profile.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

struct CanDaemon {
  TempDir dir;
  std::optional<DaemonProcess> process;
  explicit CanDaemon(std::vector<std::string> extra = {}) {
    const std::string scene = dir.write("scene.yaml", minimal_scene_text());
    std::vector<std::string> arguments{"--scene", scene, "--can", "can:vcan0", "--no-flash", "--timeout", "120"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    if (auto started = DaemonProcess::start(arguments)) process.emplace(std::move(*started));
  }
};

// candump's log line for the next frame on `id`, while `action` runs.
std::string candump_one(const std::string& filter, const std::function<void()>& action) {
  auto candump = DaemonProcess::start_program("candump", {"-L", "-n", "1", "-T", "5000", "vcan0," + filter});
  if (!candump) return "(candump did not start)";
  std::this_thread::sleep_for(300ms);  // candump binds before the request goes out
  action();
  candump->wait_ready(6s);  // collects stdout until candump exits
  candump->wait();
  const std::string text = candump->stdout_text();
  const auto space = text.rfind(' ');
  return space == std::string::npos ? text : text.substr(space + 1, text.find('\n', space) - space - 1);
}

TEST(DaemonVcan, CansendGetStatus_CandumpSeesTheExactSingleFrameReply) {
  LDOEM_REQUIRE_VCAN0();
  CanDaemon daemon;
  ASSERT_TRUE(daemon.process && daemon.process->wait_ready()) << daemon.process->stderr_text();
  EXPECT_EQ(daemon.process->endpoints().at("can"), "vcan0 6C0:6C1");
  const std::string reply = candump_one("6C1:7FF", [] {
    EXPECT_EQ(DaemonProcess::start_program("cansend", {"vcan0", "6C0#020102"})->wait(), std::optional<int>(0));
  });
  EXPECT_EQ(reply, "6C1#06810200000001");  // GET_STATUS reply, IDLE, unpadded (D1)
}

TEST(DaemonVcan, GetProfileOverIsoTp_ArrivesWholeAndDecodes) {
  LDOEM_REQUIRE_VCAN0();
  CanDaemon daemon({"--time-scale", "4"});
  ASSERT_TRUE(daemon.process && daemon.process->wait_ready()) << daemon.process->stderr_text();
  IsoTpHost host(CanIdPair{0x6C0, 0x6C1});
  EXPECT_EQ(host.exchange(telegram("TRANS_ROTATE 0000")), std::optional<Bytes>(telegram("TRANS_ROTATE reply 0000 0002")));
  EXPECT_EQ(host.exchange(telegram("TRANS_MEASURE")), std::optional<Bytes>(telegram("TRANS_MEASURE reply 0000 0003 0000")));
  const auto payload = host.exchange(telegram("GET_PROFILE 0001 39ff"));  // multi-frame, FF + CFs
  ASSERT_TRUE(payload);
  const auto profile = protocol::decode_profile(*payload);
  ASSERT_TRUE(profile) << to_hex(*payload);
  EXPECT_EQ(profile->profile_sent, 1);
  EXPECT_EQ(distance_at_angle_zero(*profile), std::optional<std::uint16_t>(1280));  // the wall, 5 m ahead
}

TEST(DaemonVcan, SecondHostOnAnotherIdPair_IsItsOwnConnection) {
  LDOEM_REQUIRE_VCAN0();
  CanDaemon daemon({"--can", "can:vcan0:6C0:6C1", "--can", "can:vcan0:6C2:6C3"});
  ASSERT_TRUE(daemon.process && daemon.process->wait_ready()) << daemon.process->stderr_text();
  IsoTpHost first(CanIdPair{0x6C0, 0x6C1});
  IsoTpHost second(CanIdPair{0x6C2, 0x6C3});
  EXPECT_EQ(first.exchange(telegram("GET_STATUS")), std::optional<Bytes>(telegram("GET_STATUS reply 0000 0001")));
  EXPECT_EQ(second.exchange(telegram("GET_CONFIG 0010")),
            std::optional<Bytes>(telegram("GET_CONFIG reply 0010 0001 000a 0004")));
  EXPECT_FALSE(first.next(300ms).has_value());  // the second host's reply went only to it
}

// Issue 15: two scanners of one daemon share vcan0, each on its own identifier pair (scanner k:
// 0x6C0 + 2k / 0x6C1 + 2k). Each host hears only its scanner, and each profile is seen from that
// scanner's place: the wall is 5 m ahead of `near`, 6 m ahead of `far` (1 m behind, 1 m aside).
TEST(DaemonVcan, TwoScannersOnOneBus_EachAnswersOnItsOwnPairFromItsOwnPlace) {
  LDOEM_REQUIRE_VCAN0();
  TempDir dir;
  const std::string scene = dir.write("two.yaml", minimal_scene_text() +
                                                      "scanners:\n"
                                                      "  - {name: near}\n"
                                                      "  - {name: far, pivot_pose: {position_m: [-1, 1, 0]}}\n");
  auto process = DaemonProcess::start(
      {"--scene", scene, "--can", "can:vcan0", "--no-flash", "--time-scale", "4", "--timeout", "120"});
  ASSERT_TRUE(process && process->wait_ready()) << (process ? process->stderr_text() : "");
  EXPECT_NE(process->stdout_text().find("scanner near\ncan vcan0 6C0:6C1\nscanner far\ncan vcan0 6C2:6C3\n"),
            std::string::npos)
      << process->stdout_text();
  IsoTpHost near(CanIdPair{0x6C0, 0x6C1});
  IsoTpHost far(CanIdPair{0x6C2, 0x6C3});
  const std::vector<std::pair<IsoTpHost*, std::uint16_t>> hosts{{&near, 1280}, {&far, 1536}};  // 5 m, 6 m
  for (const auto& [host, expected_q8_m] : hosts) {
    EXPECT_EQ(host->exchange(telegram("TRANS_ROTATE 0000")), std::optional<Bytes>(telegram("TRANS_ROTATE reply 0000 0002")));
    EXPECT_EQ(host->exchange(telegram("TRANS_MEASURE")), std::optional<Bytes>(telegram("TRANS_MEASURE reply 0000 0003 0000")));
    const auto payload = host->exchange(telegram("GET_PROFILE 0001 39ff"));
    ASSERT_TRUE(payload);
    const auto profile = protocol::decode_profile(*payload);
    ASSERT_TRUE(profile) << to_hex(*payload);
    EXPECT_EQ(distance_at_angle_zero(*profile), std::optional<std::uint16_t>(expected_q8_m));
  }
  EXPECT_FALSE(near.next(300ms).has_value());  // none of far's replies reached near's pair
  // far is still rotating, near measuring: each pair reports its own scanner's state.
  EXPECT_EQ(far.exchange(telegram("TRANS_ROTATE 0000")), std::optional<Bytes>(telegram("TRANS_ROTATE reply 0000 0002")));
  EXPECT_EQ(near.exchange(telegram("GET_STATUS")), std::optional<Bytes>(telegram("GET_STATUS reply 0000 0003")));
}

// With --virtual-time, a request heard while the daemon idles (its 50 ms wait for hosts) must
// still give the host its wall-time grace for flow control: the 8-byte TRANS_MEASURE reply is a
// first frame that waits for ours (regression: the clock jumped over N_Bs and dropped it).
TEST(DaemonVcan, VirtualTimeAfterIdling_MultiFrameReplyWaitsForTheHostsFlowControl) {
  LDOEM_REQUIRE_VCAN0();
  CanDaemon daemon({"--virtual-time"});
  ASSERT_TRUE(daemon.process && daemon.process->wait_ready()) << daemon.process->stderr_text();
  IsoTpHost host(CanIdPair{0x6C0, 0x6C1});
  std::this_thread::sleep_for(1200ms);  // longer than the grace: the daemon is idle
  EXPECT_EQ(host.exchange(telegram("TRANS_ROTATE 0000")), std::optional<Bytes>(telegram("TRANS_ROTATE reply 0000 0002")));
  std::this_thread::sleep_for(1200ms);
  EXPECT_EQ(host.exchange(telegram("TRANS_MEASURE")), std::optional<Bytes>(telegram("TRANS_MEASURE reply 0000 0003 0000")));
}

// D9 bus_timing with SET_CONFIG key 0x0002 BITRATE 1 (125 kbit/s, D1): a 2.2 kB profile takes
// about 280 ms on the bus, so at 10 Hz revolutions are skipped while it is sent (D10):
// PROFILECOUNT jumps by 3 or more between consecutive profiles, PROFILESENT stays consecutive.
TEST(DaemonVcan, BusTimingAt125k_SlowsProfilesSoRevolutionsAreSkipped) {
  LDOEM_REQUIRE_VCAN0();
  TempDir dir;
  const std::string scene = dir.write("scene.yaml", "effects: [bus_timing]\n" + minimal_scene_text());
  auto process = DaemonProcess::start({"--scene", scene, "--can", "can:vcan0", "--no-flash", "--virtual-time", "--timeout", "120"});
  ASSERT_TRUE(process && process->wait_ready()) << (process ? process->stderr_text() : "");
  IsoTpHost host(CanIdPair{0x6C0, 0x6C1});
  EXPECT_EQ(host.exchange(telegram("SET_CONFIG 0002 0001 06c0 06c1 0000 0000")),
            std::optional<Bytes>(telegram("SET_CONFIG reply 0000")));
  EXPECT_EQ(host.exchange(telegram("TRANS_ROTATE 0000")), std::optional<Bytes>(telegram("TRANS_ROTATE reply 0000 0002")));
  EXPECT_EQ(host.exchange(telegram("TRANS_MEASURE")), std::optional<Bytes>(telegram("TRANS_MEASURE reply 0000 0003 0000")));
  host.send(telegram("GET_PROFILE 0004 39ff"));
  std::vector<protocol::Profile> profiles;
  while (profiles.size() < 4) {
    const auto payload = host.next();
    ASSERT_TRUE(payload) << "after " << profiles.size() << " profiles";
    auto profile = protocol::decode_profile(*payload);
    ASSERT_TRUE(profile) << to_hex(*payload);
    profiles.push_back(*profile);
  }
  for (std::size_t i = 1; i < profiles.size(); ++i) {
    EXPECT_EQ(profiles[i].profile_sent, profiles[i - 1].profile_sent + 1);
    EXPECT_GE(profiles[i].profile_count - profiles[i - 1].profile_count, 3) << i;
  }
}

}  // namespace
}  // namespace ldoem::daemon::test
