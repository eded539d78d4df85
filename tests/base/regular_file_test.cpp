// open_regular_file / read_regular_file (issue 27): what is not a regular file is refused at
// once and named; the read bound counts bytes read, not st_size.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "ldoem/base/regular_file.hpp"

namespace ldoem::base {
namespace {

class RegularFile : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (std::filesystem::temp_directory_path() / "ldoem-regular-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    folder_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::filesystem::path folder_;
};

TEST_F(RegularFile, AFifoIsRefusedForReadingAndForWritingWithoutWaiting) {
  const auto fifo = folder_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto read = open_regular_file(fifo, O_RDONLY);  // O_NONBLOCK: returns although no writer exists
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error().text, "is a FIFO, not a regular file");
  auto write = open_regular_file(fifo, O_WRONLY | O_CREAT | O_TRUNC);  // ENXIO without a reader
  ASSERT_FALSE(write);
  EXPECT_EQ(write.error().text, "is a FIFO, not a regular file");
}

TEST_F(RegularFile, FoldersAndDevicesAreNamed) {
  EXPECT_EQ(open_regular_file(folder_, O_RDONLY).error().text, "is a directory, not a regular file");
  EXPECT_EQ(open_regular_file(folder_, O_WRONLY | O_CREAT).error().text, "is a directory, not a regular file");
  EXPECT_EQ(open_regular_file("/dev/zero", O_RDONLY).error().text, "is a character device, not a regular file");
  EXPECT_EQ(open_regular_file("/dev/null", O_WRONLY | O_CREAT | O_TRUNC).error().text,
            "is a character device, not a regular file");
}

TEST_F(RegularFile, MissingFileIsCreatedWithOCreatAndAnErrnoOtherwise) {
  auto missing = open_regular_file(folder_ / "none", O_RDONLY);
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().error_number, ENOENT);
  auto created = open_regular_file(folder_ / "new", O_WRONLY | O_CREAT | O_TRUNC);
  ASSERT_TRUE(created) << created.error().text;
  EXPECT_EQ(::fcntl(created->get(), F_GETFL) & O_NONBLOCK, 0);
  EXPECT_TRUE(std::filesystem::is_regular_file(folder_ / "new"));
}

TEST_F(RegularFile, ReadIsBoundedByWhatIsRead) {
  const auto path = folder_ / "text";
  { std::ofstream(path) << std::string(1000, 'a'); }
  auto whole = read_regular_file(path, 1000);
  ASSERT_TRUE(whole);
  EXPECT_EQ(whole->size(), 1000u);
  auto over = read_regular_file(path, 999);
  ASSERT_FALSE(over);
  EXPECT_EQ(over.error().error_number, EFBIG);
  // st_size is 0 for /proc files; their bytes are still counted (and they are regular files).
  auto proc = read_regular_file("/proc/self/status", 16);
  ASSERT_FALSE(proc);
  EXPECT_EQ(proc.error().error_number, EFBIG);
}

}  // namespace
}  // namespace ldoem::base
