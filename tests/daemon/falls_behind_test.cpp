// L-time-1 pinned on TCP and on the serial pty: SIGSTOP for 0.3 s and 1.0 s mid-stream at
// 10 Hz, then SIGCONT; the stop shows as skipped revolutions on the device's clock
// (falls_behind.hpp). The vcan variant is falls_behind_vcan_test.cpp (inside UML).
#include <gtest/gtest.h>

#include "falls_behind.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

void over_tcp(std::chrono::milliseconds stop) {
  TempDir dir;
  auto daemon = start_real_time_daemon(dir, {"--no-can", "--tcp", "tcp:127.0.0.1:0"});
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  expect_stop_is_skipped(*daemon, driver::TcpEndpoint{"127.0.0.1", daemon->tcp_port()}, stop);
}

void over_serial(std::chrono::milliseconds stop) {
  TempDir dir;
  auto daemon = start_real_time_daemon(dir, {"--no-can", "--serial", "serial:pty:" + dir.path("serial")});
  ASSERT_TRUE(daemon && daemon->wait_ready()) << (daemon ? daemon->stderr_text() : "");
  expect_stop_is_skipped(*daemon, driver::SerialEndpoint{dir.path("serial")}, stop);
}

TEST(DaemonFallsBehind, Tcp_Stopped300ms_SkipsTheRevolutions) { over_tcp(300ms); }
TEST(DaemonFallsBehind, Tcp_Stopped1s_SkipsTheRevolutions) { over_tcp(1000ms); }
TEST(DaemonFallsBehind, Serial_Stopped300ms_SkipsTheRevolutions) { over_serial(300ms); }
TEST(DaemonFallsBehind, Serial_Stopped1s_SkipsTheRevolutions) { over_serial(1000ms); }

}  // namespace
}  // namespace ldoem::daemon::test
