// Issue 11, daemon lifetime and limits, each driven from outside like a hostile or unlucky user:
// an unreadable or corrupt flash, clients closed during the exit flush, connection numbers that
// wrap, hosts that switch ECHO on, stall inside a frame or never speak.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "daemon_process.hpp"
#include "host_link.hpp"

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
                                     "127.0.0.1:0", "--virtual-time", "--timeout", "120"};
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
  EXPECT_NE(text.find("flash " + flash + ": cannot read: Is a directory"), std::string::npos) << text;
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

}  // namespace
}  // namespace ldoem::daemon::test
