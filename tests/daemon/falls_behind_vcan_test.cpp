// L-time-1 pinned on vcan0 (inside User-Mode Linux, label vcan): the daemon on CAN stopped for
// 0.3 s and 1.0 s mid-stream at 10 Hz (falls_behind.hpp). FAILS without vcan0, never skips.
#include <gtest/gtest.h>

#include "falls_behind.hpp"
#include "ldoem/test_support/require_vcan.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

void over_vcan(std::chrono::milliseconds stop) {
  TempDir dir;
  auto daemon = start_real_time_daemon(dir, {"--can", "can:vcan0"});
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  expect_stop_is_skipped(*daemon, driver::CanEndpoint{"vcan0"}, stop);
}

TEST(DaemonFallsBehind, Vcan_Stopped300ms_SkipsTheRevolutions) {
  LDOEM_REQUIRE_VCAN0();
  over_vcan(300ms);
}
TEST(DaemonFallsBehind, Vcan_Stopped1s_SkipsTheRevolutions) {
  LDOEM_REQUIRE_VCAN0();
  over_vcan(1000ms);
}

}  // namespace
}  // namespace ldoem::daemon::test
