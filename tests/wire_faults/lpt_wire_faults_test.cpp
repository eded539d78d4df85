// D11 wire faults on the pseudo-LPT (D8, the pty back end): lpt_lose_steps and lpt_jam, produced
// inside the LPT endpoint. The wire effect is the number of steps the tilt plate followed
// (query-status tilt_steps, the drive board's count) against the pulses written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <signal.h>

#include <algorithm>
#include <thread>

#include "ldoem/faults/fault_scheduler.hpp"

#include "ldoem/protocol/lpt.hpp"
#include "wire_fault_support.hpp"

namespace ldoem::wire_faults::test {
namespace {

using namespace std::chrono_literals;
using daemon::test::minimal_scene_text;
using daemon::test::TcpHost;
using daemon::test::telegram;
using daemon::test::to_hex;
using nlohmann::json;

struct LptDaemon {
  TempDir pty_dir;
  std::string control = pty_dir.path("ctl.sock");
  FaultyDaemon daemon;
  int lpt = -1;

  explicit LptDaemon(const std::string& faults, std::uint64_t seed = 0)
      : daemon(minimal_scene_text() + "seed: " + std::to_string(seed) + "\nfaults:\n" + faults,
               {"--lpt", "lpt:pty:" + pty_dir.path("lpt"), "--control", control}) {
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

// Same scene, seed and conversation: the same steps lost, the same replies and the same event log,
// twice. Lost steps are started by a probability trigger (D11: counter-based draws from the seed)
// and by a counted one, both on GET_STATUS over TCP; between two requests the host pulses 5 steps.
TEST(WireFaultsLpt, SameSeedAndConversationGiveTheSameStepsAndEventsTwice) {
  constexpr std::uint64_t kSeed = 23;
  constexpr double kProbability = 0.4;
  constexpr int kRounds = 12;
  constexpr int kPulses = 5;
  const std::string faults = "  - {kind: lpt_lose_steps, count: 2, probability: 0.4, service: GET_STATUS}\n"
                             "  - {kind: lpt_lose_steps, count: 3, every: {service: GET_STATUS, count: 4}}\n";
  // What the scheduler must do, worked out apart from it: the n-th GET_STATUS (from 0) starts the
  // first entry when fault_draw(seed, 0, n) < p, the second on every 4th; each activation loses
  // its count of the next steps.
  std::vector<std::uint64_t> expected_steps;
  {
    std::uint64_t pending = 0;
    std::uint64_t steps = 0;
    for (int n = 0; n < kRounds; ++n) {
      if (faults::fault_draw(kSeed, 0, static_cast<std::uint64_t>(n)) < kProbability) pending += 2;
      if ((n + 1) % 4 == 0) pending += 3;
      const std::uint64_t lost = std::min<std::uint64_t>(pending, kPulses);
      pending -= lost;
      steps += kPulses - lost;
      expected_steps.push_back(steps);
    }
  }
  ASSERT_LT(expected_steps.back(), static_cast<std::uint64_t>(kRounds * kPulses));  // some steps are lost
  auto run = [&] {
    LptDaemon d(faults, kSeed);
    EXPECT_GE(d.lpt, 0) << d.daemon.diagnostics();
    std::string transcript;
    auto host = TcpHost::connect(d.daemon.process->tcp_port());
    if (d.lpt < 0 || !host) return std::pair<std::string, std::string>{};
    for (int round = 0; round < kRounds; ++round) {
      host->send(telegram("GET_STATUS"));
      const auto reply = host->next_frame(5s);
      d.pulse(kPulses);
      const auto steps = d.tilt_steps_when(expected_steps[static_cast<std::size_t>(round)]);
      transcript += (reply ? to_hex(*reply) : std::string("(nothing)")) + " steps " +
                    (steps ? std::to_string(*steps) : std::string("(no answer)")) + "\n";
    }
    d.daemon.process->signal(SIGTERM);
    d.daemon.process->wait();
    return std::pair{transcript, d.daemon.events()};
  };
  const auto first = run_twice_expect_same(run);
  std::string expected_tail;
  for (const std::uint64_t steps : expected_steps) expected_tail += " steps " + std::to_string(steps) + "\n";
  std::string steps_seen;
  for (std::size_t at = first.first.find(" steps "); at != std::string::npos; at = first.first.find(" steps ", at + 1)) {
    steps_seen += first.first.substr(at, first.first.find('\n', at) + 1 - at);
  }
  EXPECT_EQ(steps_seen, expected_tail) << first.first;
  EXPECT_NE(first.second.find("probability"), std::string::npos) << first.second;
  EXPECT_NE(first.second.find("\"reason\":\"count used\""), std::string::npos) << first.second;
}

}  // namespace
}  // namespace ldoem::wire_faults::test
