// D11 wire faults on the pseudo-LPT (D8, the pty back end): lpt_lose_steps and lpt_jam, produced
// inside the LPT endpoint. The wire effect is the number of steps the tilt plate followed
// (query-status tilt_steps, the drive board's count) against the pulses written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <thread>

#include "ldoem/protocol/lpt.hpp"
#include "wire_fault_support.hpp"

namespace ldoem::wire_faults::test {
namespace {

using namespace std::chrono_literals;
using daemon::test::minimal_scene_text;
using nlohmann::json;

struct LptDaemon {
  TempDir pty_dir;
  std::string control = pty_dir.path("ctl.sock");
  FaultyDaemon daemon;
  int lpt = -1;

  explicit LptDaemon(const std::string& faults)
      : daemon(minimal_scene_text() + "faults:\n" + faults, {"--lpt", "pty:" + pty_dir.path("lpt"), "--control", control}) {
    if (daemon.ready()) lpt = open_raw(pty_dir.path("lpt"));
  }
  ~LptDaemon() {
    if (lpt >= 0) ::close(lpt);
  }
  // `count` full steps with DIR = 1: each a rising then a falling clock edge (D8).
  void pulse(int count) {
    std::string bytes;
    for (int i = 0; i < count; ++i) {
      bytes += static_cast<char>(protocol::kLptDirectionBit | protocol::kLptClockBit);
      bytes += static_cast<char>(protocol::kLptDirectionBit);
    }
    ASSERT_EQ(::write(lpt, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  }
  std::optional<std::uint64_t> tilt_steps() {
    const auto status = control_request(control, {{"execute", "query-status"}});
    if (!status || !status->contains("return")) return std::nullopt;
    return (*status)["return"]["tilt_steps"].get<std::uint64_t>();
  }
  // tilt_steps once it equals `expected` (the pty hands bytes on asynchronously), or the last seen.
  std::optional<std::uint64_t> tilt_steps_when(std::uint64_t expected) {
    std::optional<std::uint64_t> seen;
    for (int attempt = 0; attempt < 50 && seen != expected; ++attempt) {
      seen = tilt_steps();
      if (seen != expected) std::this_thread::sleep_for(50ms);
    }
    std::this_thread::sleep_for(200ms);  // and it stays there: no step arrives late
    return tilt_steps();
  }
};

TEST(WireFaultsLpt, LoseSteps_ThePlateMissesExactlyCountSteps) {
  LptDaemon d("  - {kind: lpt_lose_steps, count: 3}\n");
  ASSERT_GE(d.lpt, 0) << d.daemon.diagnostics();
  d.pulse(10);
  EXPECT_EQ(d.tilt_steps_when(7), std::optional<std::uint64_t>(7));
  d.pulse(10);  // the count is used up
  EXPECT_EQ(d.tilt_steps_when(17), std::optional<std::uint64_t>(17));
  EXPECT_NE(d.daemon.events().find("\"reason\":\"count used\""), std::string::npos) << d.daemon.events();
}

TEST(WireFaultsLpt, Jam_ThePlateFollowsNoPulseUntilCleared) {
  LptDaemon d("  - {kind: lpt_jam}\n");
  ASSERT_GE(d.lpt, 0) << d.daemon.diagnostics();
  d.pulse(25);
  EXPECT_EQ(d.tilt_steps_when(0), std::optional<std::uint64_t>(0));
  const auto cleared = control_request(d.control, {{"execute", "clear-fault"}});
  ASSERT_TRUE(cleared && cleared->contains("return")) << (cleared ? cleared->dump() : "no answer");
  d.pulse(4);
  EXPECT_EQ(d.tilt_steps_when(4), std::optional<std::uint64_t>(4));
}

}  // namespace
}  // namespace ldoem::wire_faults::test
