// The paper's corridor scanned end to end over TCP (any host): ldoem-emud, optionally ldoem-hub,
// and ldoem-scan as separate processes, exactly as a user runs them. Virtual time (D7) makes each
// scan take seconds and, since the noise is keyed by seed, revolution and beam (D6), makes it
// reproducible byte for byte.
#include <gtest/gtest.h>

#include <cstdlib>

#include "corridor_expectations.hpp"
#include "corridor_scan.hpp"

namespace ldoem::e2e {
namespace {

TEST(CorridorTcp, PaperScan_FitsCylinderAndWallWithinTolerance) {
  TempDir dir;
  const ScanRun run = scan_corridor(dir, "tcp", Route::tcp);
  expect_paper_scan(run);
}

TEST(CorridorTcp, SameScanTwice_GivesByteIdenticalPly) {
  TempDir dir;
  const ScanRun first = scan_corridor(dir, "first", Route::tcp);
  const ScanRun second = scan_corridor(dir, "second", Route::tcp);
  ASSERT_EQ(first.exit_status, 0) << first.failure;
  ASSERT_EQ(second.exit_status, 0) << second.failure;
  expect_same_bytes(first, second, "two TCP scans");
}

// The cloud as recorded when the scan became organised with the fields t range azimuth tilt
// (issue 24; before that, 9a8aba61... from issue 9 on, unorganised x y z intensity ring):
// refactoring must not move a single byte. sha256sum (coreutils) hashes the file.
constexpr const char* kCorridorPlySha256 = "c9bfe88673eb28ba18455bfcd3ade0e17d78c790247f4fa2c7e655bd3c04a16a";

TEST(CorridorTcp, Cloud_IsByteIdenticalToTheRecordedOne) {
  TempDir dir;
  const ScanRun run = scan_corridor(dir, "recorded", Route::tcp);
  ASSERT_EQ(run.exit_status, 0) << run.failure;
  auto hash = ChildProcess::start("/usr/bin/sha256sum", {run.ply_path}, dir.path("sha256sum"));
  ASSERT_TRUE(hash.has_value());
  ASSERT_EQ(hash->wait(std::chrono::seconds(60)), std::optional<int>(0)) << hash->stderr_text();
  EXPECT_EQ(hash->stdout_text().substr(0, 64), kCorridorPlySha256);
}

TEST(CorridorTcp, ScanThroughHub_GivesTheSameBytesAsDirect) {
  TempDir dir;
  const ScanRun direct = scan_corridor(dir, "direct", Route::tcp);
  const ScanRun via_hub = scan_corridor(dir, "hub", Route::hub_tcp);
  ASSERT_EQ(direct.exit_status, 0) << direct.failure;
  ASSERT_EQ(via_hub.exit_status, 0) << via_hub.failure;
  expect_same_bytes(direct, via_hub, "direct TCP vs ldoem-hub over TCP");
}

// scripts/scan-corridor.sh (what scripts/demo.sh runs) over TCP: the fit table beside the truth.
TEST(CorridorTcp, ScanCorridorScript_PrintsFitBesideTrueValues) {
  TempDir dir;
  auto script = ChildProcess::start(
      std::string(LDOEM_SOURCE_DIR) + "/scripts/scan-corridor.sh",
      {"--out-dir", dir.path("out"), "--transport", "tcp", "--virtual-time"}, dir.path("script"),
      {std::string("LDOEM_EMUD=") + LDOEM_EMUD_PATH, std::string("LDOEM_SCAN=") + LDOEM_SCAN_PATH});
  ASSERT_TRUE(script.has_value());
  const auto status = script->wait(std::chrono::seconds(300));
  ASSERT_EQ(status, std::optional<int>(0)) << script->stdout_text() << script->stderr_text();
  const std::string printed = script->stdout_text();
  EXPECT_NE(printed.find("cylinder diameter"), std::string::npos) << printed;
  EXPECT_NE(printed.find("195.0 mm"), std::string::npos) << printed;  // the true value column
  EXPECT_NE(printed.find("4.180 m"), std::string::npos) << printed;
  const auto fit = parse_tool_fit(printed);
  ASSERT_TRUE(fit.has_value()) << printed;
  expect_paper_fit(*fit, "scan-corridor.sh");
  EXPECT_FALSE(read_file(dir.path("out/corridor.png")).empty());
}

}  // namespace
}  // namespace ldoem::e2e
