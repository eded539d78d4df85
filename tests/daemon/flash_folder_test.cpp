// Issue 24: without --flash or --flash-dir the flash goes to the state folder ($STATE_DIRECTORY,
// else $XDG_STATE_HOME/ldoem, else ~/.local/state/ldoem), made on first use, and never beside the
// scene: following the docs from a clone must not write into the repository.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "daemon_process.hpp"

namespace ldoem::daemon::test {
namespace {

TEST(FlashFolder, WithoutFlashOptions_TheFlashGoesToXdgStateHomeNotBesideTheScene) {
  TempDir scenes;
  TempDir home;
  const std::string scene = scenes.write("scene.yaml", minimal_scene_text());
  auto process = DaemonProcess::start_program(
      "env", {"-u", "STATE_DIRECTORY", "-u", "XDG_STATE_HOME", "HOME=" + home.path(""), LDOEM_EMUD_PATH, "--scene",
              scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--virtual-time", "--timeout", "120"});
  ASSERT_TRUE(process);
  ASSERT_TRUE(process->wait_ready()) << process->stderr_text();
  process->signal(SIGTERM);
  EXPECT_EQ(process->wait(), std::optional<int>(128 + SIGTERM)) << process->stderr_text();

  const std::filesystem::path folder = std::filesystem::path(home.path(".local")) / "state" / "ldoem";
  std::ifstream saved(folder / "scene.yaml.flash");
  std::string first_line;
  std::getline(saved, first_line);
  EXPECT_EQ(first_line, "ldoem-flash 1");
  struct stat info {};
  ASSERT_EQ(::stat(folder.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0700u);  // XDG: a state folder the program makes is 0700
  for (const auto& entry : std::filesystem::directory_iterator(scenes.path(""))) {
    EXPECT_EQ(entry.path().filename(), "scene.yaml") << "written beside the scene: " << entry.path();
  }
}

}  // namespace
}  // namespace ldoem::daemon::test
