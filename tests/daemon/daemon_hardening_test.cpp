// Issue 11, daemon lifetime and limits, each driven from outside like a hostile or unlucky user:
// an unreadable or corrupt flash, clients closed during the exit flush, connection numbers that
// wrap, hosts that switch ECHO on, stall inside a frame or never speak.
#include <fcntl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/protocol/serial_framing.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::optional<DaemonProcess> start_daemon(const TempDir& dir, std::vector<std::string> extra) {
  std::vector<std::string> arguments{"--scene", dir.write("scene.yaml", minimal_scene_text()), "--no-can", "--tcp",
                                     "tcp:127.0.0.1:0", "--virtual-time", "--timeout", "120"};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  return DaemonProcess::start(arguments);
}

// ------------------------------------------------------------------------------------- flash

TEST(DaemonFlash, CorruptFlash_StopsStartUpWithExitTwoAndLeavesTheFileAlone) {
  TempDir dir;
  const std::string flash = dir.write("scene.flash", "my hand-edited flash with a typo\n");
  auto process = start_daemon(dir, {"--flash", flash});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  const std::string text = process->stderr_text();
  EXPECT_NE(text.find("flash " + flash + ":1:"), std::string::npos) << text;
  EXPECT_NE(text.find("--reset-flash"), std::string::npos) << text;
  EXPECT_EQ(read_file(flash), "my hand-edited flash with a typo\n");
}

TEST(DaemonFlash, UnreadableFlash_StopsStartUpWithExitTwo) {
  TempDir dir;
  const std::string flash = dir.path("scene.flash");
  ASSERT_EQ(::mkdir(flash.c_str(), 0755), 0);  // read() fails with EISDIR, also for root
  auto process = start_daemon(dir, {"--flash", flash});
  ASSERT_TRUE(process);
  EXPECT_EQ(process->wait(), std::optional<int>(2));
  const std::string text = process->stderr_text();
  EXPECT_NE(text.find("flash " + flash + ": is a directory, not a regular file"), std::string::npos) << text;
  EXPECT_TRUE(std::filesystem::is_directory(flash));
}

TEST(DaemonFlash, ResetFlash_StartsFromTheDefaultsAndReplacesTheFileAtExit) {
  TempDir dir;
  const std::string flash = dir.write("scene.flash", "garbage\n");
  auto process = start_daemon(dir, {"--flash", flash, "--reset-flash"});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  EXPECT_NE(process->stderr_text().find("--reset-flash: starting from the scene's defaults"), std::string::npos);
  process->signal(SIGTERM);
  EXPECT_EQ(process->wait(), std::optional<int>(128 + SIGTERM));
  EXPECT_EQ(read_file(flash).rfind("ldoem-flash 1\n", 0), 0u) << read_file(flash);
}

TEST(DaemonFlash, MissingFlash_IsAFirstPowerUpNotAnError) {
  TempDir dir;
  const std::string flash = dir.path("scene.flash");
  auto process = start_daemon(dir, {"--flash", flash});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  process->signal(SIGTERM);
  EXPECT_EQ(process->wait(), std::optional<int>(128 + SIGTERM));
  EXPECT_EQ(read_file(flash).rfind("ldoem-flash 1\n", 0), 0u);
}

// -------------------------------------------------------------------------------- serial echo

// A host that puts its side of the serial pty back into a mode with ECHO (without ECHOCTL, so
// STX/ETX come back as they are) got every reply back as a request: hundreds of replies a second,
// without end. Now the daemon switches ECHO off before it writes, and the host gets one reply.
TEST(DaemonSerial, HostSwitchingEchoOn_GetsOneReplyNotAFeedbackLoop) {
  TempDir dir;
  auto process = start_daemon(dir, {"--no-flash", "--serial", "serial:pty:" + dir.path("serial")});
  ASSERT_TRUE(process && process->wait_ready()) << (process ? process->stderr_text() : "");
  const int fd = ::open(dir.path("serial").c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  termios settings{};
  ASSERT_EQ(::tcgetattr(fd, &settings), 0);
  ::cfmakeraw(&settings);
  settings.c_lflag |= ECHO;
  settings.c_lflag &= ~static_cast<tcflag_t>(ECHOCTL);
  ASSERT_EQ(::tcsetattr(fd, TCSANOW, &settings), 0);
  const std::string request = "\x02" "00100003000001026d36" "\x03";  // GET_STATUS, spec 7.4
  ASSERT_EQ(::write(fd, request.data(), request.size()), static_cast<ssize_t>(request.size()));
  std::string received;
  const auto until = std::chrono::steady_clock::now() + 1500ms;  // the loop answered ~300 per second
  while (std::chrono::steady_clock::now() < until) {
    if (!wait_readable(fd, 100ms)) continue;
    char buffer[4096];
    const ssize_t count = ::read(fd, buffer, sizeof buffer);
    if (count > 0) received.append(buffer, static_cast<std::size_t>(count));
  }
  const Bytes expected = protocol::encode_serial_reply(telegram("GET_STATUS reply 0000 0001"));
  EXPECT_EQ(received, std::string(expected.begin(), expected.end()));
  ASSERT_EQ(::tcgetattr(fd, &settings), 0);
  EXPECT_EQ(settings.c_lflag & ECHO, 0u);
  EXPECT_NE(process->stderr_text().find("the host switched ECHO on"), std::string::npos) << process->stderr_text();
  ::close(fd);
}

}  // namespace
}  // namespace ldoem::daemon::test
