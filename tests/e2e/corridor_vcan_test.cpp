// The paper's corridor scanned over real SocketCAN (vcan0, ISO-TP D1): only inside User-Mode
// Linux (scripts/uml/run.sh -- ctest --test-dir BUILD -L vcan). Without vcan0 these tests FAIL,
// they never skip (docs/uml-harness.md).
#include <gtest/gtest.h>
#include <net/if.h>

#include "corridor_expectations.hpp"
#include "corridor_scan.hpp"

namespace ldoem::e2e {
namespace {

#define LDOEM_E2E_REQUIRE_VCAN0() \
  ASSERT_NE(if_nametoindex("vcan0"), 0U) << "no vcan0: run inside scripts/uml/run.sh (docs/uml-harness.md)"

TEST(CorridorVcan, PaperScanOverCan_FitsCylinderAndWallWithinTolerance) {
  LDOEM_E2E_REQUIRE_VCAN0();
  TempDir dir;
  const ScanRun run = scan_corridor(dir, "can", Route::can);
  expect_paper_scan(run);
}

// Same scene, seed and command sequence through three routes: the cloud must not depend on the wire.
TEST(CorridorVcan, CanTcpAndHub_GiveByteIdenticalPly) {
  LDOEM_E2E_REQUIRE_VCAN0();
  TempDir dir;
  const ScanRun can = scan_corridor(dir, "can", Route::can);
  const ScanRun tcp = scan_corridor(dir, "tcp", Route::tcp);
  const ScanRun hub = scan_corridor(dir, "hub", Route::hub_can);
  ASSERT_EQ(can.exit_status, 0) << can.failure;
  ASSERT_EQ(tcp.exit_status, 0) << tcp.failure;
  ASSERT_EQ(hub.exit_status, 0) << hub.failure;
  expect_same_bytes(can, tcp, "CAN vs TCP");
  expect_same_bytes(can, hub, "CAN vs ldoem-hub over CAN");
}

// What scripts/demo.sh runs inside UML, with the virtual clock to keep the suite short.
TEST(CorridorVcan, ScanCorridorScript_OverCanExitsZeroWithFit) {
  LDOEM_E2E_REQUIRE_VCAN0();
  TempDir dir;
  auto script = ChildProcess::start(
      std::string(LDOEM_SOURCE_DIR) + "/scripts/scan-corridor.sh",
      {"--out-dir", dir.path("out"), "--virtual-time"}, dir.path("script"),
      {std::string("LDOEM_EMUD=") + LDOEM_EMUD_PATH, std::string("LDOEM_SCAN=") + LDOEM_SCAN_PATH});
  ASSERT_TRUE(script.has_value());
  const auto status = script->wait(std::chrono::seconds(300));
  ASSERT_EQ(status, std::optional<int>(0)) << script->stdout_text() << script->stderr_text();
  const auto fit = parse_tool_fit(script->stdout_text());
  ASSERT_TRUE(fit.has_value()) << script->stdout_text();
  expect_paper_fit(*fit, "scan-corridor.sh over CAN");
}

}  // namespace
}  // namespace ldoem::e2e
