// FileFlashStore::save is durable and safe (issue 11): a fresh mkstemp file, fsync, rename,
// folder fsync; no fixed temporary name, so a symlink planted there is never followed, and
// nothing is left behind.
#include "ldoem/daemon/file_flash_store.hpp"

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::daemon {
namespace {

class FlashFile : public ::testing::Test {
 protected:
  test_support::TempDir dir_;
  const std::filesystem::path folder_ = dir_.folder();
};

TEST_F(FlashFile, SaveReplacesTheImageAndLeavesNoTemporaryFile) {
  FileFlashStore store(folder_ / "scene.flash");
  const protocol::Bytes first{'a', 'b', 'c'};
  const protocol::Bytes second{'x', 'y'};
  store.save(first);
  EXPECT_EQ(store.last_error(), "");
  store.save(second);
  EXPECT_EQ(store.last_error(), "");
  EXPECT_EQ(store.load(), second);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder_), {}), 1);
}

TEST_F(FlashFile, ASymlinkAtTheOldFixedTemporaryNameIsNotFollowed) {
  const auto victim = folder_ / "victim";
  { std::ofstream(victim) << "keep me"; }
  std::filesystem::create_symlink(victim, folder_ / "scene.flash.tmp");
  FileFlashStore store(folder_ / "scene.flash");
  store.save(protocol::Bytes{'n', 'e', 'w'});
  EXPECT_EQ(store.last_error(), "");
  std::ifstream in(victim);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "keep me");
}

TEST_F(FlashFile, UnwritableFolder_IsReportedAndLeavesNothing) {
  FileFlashStore store(folder_ / "missing" / "scene.flash");
  EXPECT_FALSE(store.save(protocol::Bytes{'x'}));
  EXPECT_EQ(store.last_error(), "flash " + (folder_ / "missing" / "scene.flash").string() +
                                    " not saved: mkstemp: No such file or directory");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder_), {}), 0);
}

}  // namespace
}  // namespace ldoem::daemon
