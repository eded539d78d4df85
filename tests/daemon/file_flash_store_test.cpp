// FileFlashStore::save is durable and safe (issue 11): a fresh mkstemp file, fsync, rename,
// folder fsync; no fixed temporary name, so a symlink planted there is never followed, and
// nothing is left behind.
#include "ldoem/daemon/file_flash_store.hpp"

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include "ldoem/test_support/bounded_call.hpp"
#include "ldoem/test_support/temp_dir.hpp"
#include <sys/stat.h>

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
  EXPECT_TRUE(store.save(first));
  EXPECT_TRUE(store.save(second));
  EXPECT_EQ(store.load(), second);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder_), {}), 1);
}

TEST_F(FlashFile, ASymlinkAtTheOldFixedTemporaryNameIsNotFollowed) {
  const auto victim = folder_ / "victim";
  { std::ofstream(victim) << "keep me"; }
  std::filesystem::create_symlink(victim, folder_ / "scene.flash.tmp");
  FileFlashStore store(folder_ / "scene.flash");
  EXPECT_TRUE(store.save(protocol::Bytes{'n', 'e', 'w'}));
  std::ifstream in(victim);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "keep me");
}

TEST_F(FlashFile, UnwritableFolder_IsReportedAndLeavesNothing) {
  FileFlashStore store(folder_ / "missing" / "scene.flash");
  const auto saved = store.save(protocol::Bytes{'x'});
  ASSERT_FALSE(saved);
  EXPECT_EQ(saved.error(), "flash " + (folder_ / "missing" / "scene.flash").string() +
                               " not saved: mkstemp: No such file or directory");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder_), {}), 0);
}

// Issue 27 D12: a 0-byte file was read as "never saved" and rewritten with the defaults.
TEST_F(FlashFile, AnEmptyFileIsRefused) {
  { std::ofstream(folder_ / "scene.flash"); }
  FileFlashStore store(folder_ / "scene.flash");
  auto image = store.read();
  ASSERT_FALSE(image);
  EXPECT_NE(image.error().find("empty"), std::string::npos) << image.error();
}

// Issue 27 D12: the rename replaced the link by a regular file and left the target stale.
TEST_F(FlashFile, ASymlinkedFlashIsWrittenThroughTheLink) {
  std::filesystem::create_directory(folder_ / "real");
  const auto target = folder_ / "real" / "cell.flash";
  { std::ofstream(target) << "old"; }
  std::filesystem::create_symlink("real/cell.flash", folder_ / "scene.flash");
  FileFlashStore store(folder_ / "scene.flash");
  const auto saved = store.save(protocol::Bytes{'n', 'e', 'w'});
  ASSERT_TRUE(saved) << saved.error();
  EXPECT_TRUE(std::filesystem::is_symlink(folder_ / "scene.flash"));
  EXPECT_EQ(test_support::read_file(target.string()), "new");
  EXPECT_EQ(store.load(), (protocol::Bytes{'n', 'e', 'w'}));
}

// Issue 27 D13: 200 SIGKILLs during saves left 121 ".NAME.XXXXXX" files behind.
TEST_F(FlashFile, TemporariesOfAKilledSaveAreRemovedAndNothingElse) {
  for (const char* name : {".scene.flash.Ab12Z9", ".scene.flash.000000", ".scene.flash.tmp", ".other.flash.Ab12Z9",
                           "scene.flash.Ab12Z9"}) {
    std::ofstream(folder_ / name) << "x";
  }
  std::filesystem::create_directory(folder_ / ".scene.flash.dir123");
  FileFlashStore store(folder_ / "scene.flash");
  const auto note = store.remove_stale_temporaries();
  ASSERT_TRUE(note.has_value());
  EXPECT_NE(note->find("removed 2"), std::string::npos) << *note;
  EXPECT_FALSE(std::filesystem::exists(folder_ / ".scene.flash.Ab12Z9"));
  EXPECT_FALSE(std::filesystem::exists(folder_ / ".scene.flash.000000"));
  for (const char* kept : {".scene.flash.tmp", ".other.flash.Ab12Z9", "scene.flash.Ab12Z9", ".scene.flash.dir123"}) {
    EXPECT_TRUE(std::filesystem::exists(folder_ / kept)) << kept;
  }
  EXPECT_FALSE(store.remove_stale_temporaries().has_value());
}

// Issue 27 D11: open() of a FIFO waited for a writer, with the daemon's signals blocked.
TEST_F(FlashFile, AFifoIsRefusedAtOnce) {
  const auto fifo = folder_ / "scene.flash";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto error = test_support::call_within(std::chrono::seconds(10), [fifo] {
    auto image = FileFlashStore(fifo).read();
    return image ? std::string() : image.error();
  });
  ASSERT_TRUE(error.has_value()) << "reading a FIFO flash did not return within 10 s";
  EXPECT_NE(error->find("is a FIFO"), std::string::npos) << *error;
}

}  // namespace
}  // namespace ldoem::daemon
