// Recorded and replayed over vcan0 (UML only, label vcan): the paper's scan over CAN recorded two
// ways at once, by `ldoem-emud --record` and by can-utils `candump -L`, and each recording
// replayed over vcan0 by `ldoem-emud --replay` to the same scan: the PLYs must be byte-identical.
#include <gtest/gtest.h>
#include <net/if.h>

#include <csignal>

#include "corridor_expectations.hpp"
#include "corridor_scan.hpp"

namespace ldoem::e2e {
namespace {

TEST(CorridorReplayVcan, RecordedAndCandumpCaptures_ReplayToTheSameBytes) {
  ASSERT_NE(if_nametoindex("vcan0"), 0U) << "no vcan0: run inside scripts/uml/run.sh (docs/uml-harness.md)";
  TempDir dir;
  // candump -L writes the log format of candump -l on stdout: our ChildProcess keeps it.
  // A large receive buffer: a whole profile arrives as a burst of 600+ frames.
  // stdbuf -oL: each frame's line is written at once, so stopping candump loses none.
  auto candump = ChildProcess::start("/usr/bin/stdbuf", {"-oL", "/usr/bin/candump", "-L", "-r", "16777216", "vcan0"},
                                     dir.path("candump"));
  ASSERT_TRUE(candump.has_value());
  ScanSettings live_settings;
  const std::string capture = dir.path("live.pcapng");
  live_settings.extra_daemon_args = {"--record", capture};
  const ScanRun live = scan_corridor(dir, "live", Route::can, live_settings);
  candump->stop();
  ASSERT_EQ(live.exit_status, 0) << live.failure;
  const std::string log_path = dir.write("live-candump.log", candump->stdout_text());
  ASSERT_NE(candump->stdout_text().find("6C1#"), std::string::npos) << "candump saw no reply frames";
  bool decoded = false;
  const std::string tshark = check_capture_with_tshark(dir, capture, decoded);
  EXPECT_TRUE(decoded) << tshark;
  EXPECT_NE(tshark.find(", 0 problems"), std::string::npos) << tshark;

  ScanSettings replay_settings;
  replay_settings.replay_capture = capture;
  const ScanRun replayed = scan_corridor(dir, "replayed", Route::can, replay_settings);
  ASSERT_EQ(replayed.exit_status, 0) << replayed.failure;
  expect_same_bytes(live, replayed, "live CAN scan vs ldoem-emud --replay of its --record capture");

  replay_settings.replay_capture = log_path;
  const ScanRun from_log = scan_corridor(dir, "from-candump", Route::can, replay_settings);
  ASSERT_EQ(from_log.exit_status, 0) << from_log.failure;
  expect_same_bytes(live, from_log, "live CAN scan vs ldoem-emud --replay of a candump -L log");
}

}  // namespace
}  // namespace ldoem::e2e
