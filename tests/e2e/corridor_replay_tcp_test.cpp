// Recorded and replayed (docs/replay.md, docs/capture.md): the paper's scan over TCP with
// `ldoem-emud --record`, then the same scan against `ldoem-emud --replay` of that capture. The host
// cannot tell: the PLY is byte-identical, and every request of the scan was in the recording.
#include <gtest/gtest.h>

#include "corridor_expectations.hpp"
#include "corridor_scan.hpp"

namespace ldoem::e2e {
namespace {

TEST(CorridorReplayTcp, ReplayedScan_GivesTheLiveScansBytes) {
  TempDir dir;
  ScanSettings live_settings;
  const std::string capture = dir.path("live.pcapng");
  live_settings.extra_daemon_args = {"--record", capture};
  const ScanRun live = scan_corridor(dir, "live", Route::tcp, live_settings);
  ASSERT_EQ(live.exit_status, 0) << live.failure;
  ASSERT_FALSE(read_file(capture).empty());
  bool decoded = false;
  const std::string tshark = check_capture_with_tshark(dir, capture, decoded);
  EXPECT_TRUE(decoded) << tshark;
  EXPECT_NE(tshark.find(", 0 problems"), std::string::npos) << tshark;

  ScanSettings replay_settings;
  replay_settings.replay_capture = capture;
  const ScanRun replayed = scan_corridor(dir, "replayed", Route::tcp, replay_settings);
  ASSERT_EQ(replayed.exit_status, 0) << replayed.failure;
  expect_same_bytes(live, replayed, "live TCP scan vs ldoem-emud --replay of its recording");
}

}  // namespace
}  // namespace ldoem::e2e
