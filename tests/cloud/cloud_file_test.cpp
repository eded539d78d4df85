// write_file_bytes replaces a file atomically (temporary file, fsync, rename): a reader of the
// old file keeps the old bytes, nothing is truncated in place, and no temporary file is left.
#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::cloud {
namespace {

class CloudFileWrite : public ::testing::Test {
 protected:
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(folder_), {}));
  }
  test_support::TempDir dir_;
  const std::filesystem::path folder_ = dir_.folder();
};

TEST_F(CloudFileWrite, ReplacesTheFileWithoutTruncatingItInPlace) {
  const auto path = folder_ / "scan.ply";
  ASSERT_TRUE(write_file_bytes(path, "old contents"));
  const int reader = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(reader, 0);
  ASSERT_TRUE(write_file_bytes(path, "new"));
  // The old file's reader still sees every old byte: the new file is a different inode.
  char buffer[64] = {};
  const ssize_t got = ::pread(reader, buffer, sizeof buffer, 0);
  ::close(reader);
  EXPECT_EQ(std::string(buffer, static_cast<std::size_t>(std::max<ssize_t>(got, 0))), "old contents");
  auto now = read_file_bytes(path);
  ASSERT_TRUE(now);
  EXPECT_EQ(*now, "new");
  EXPECT_EQ(entries(), 1u) << "a temporary file was left behind";
  EXPECT_EQ(std::filesystem::status(path).permissions() & std::filesystem::perms::others_read,
            std::filesystem::perms::others_read);
}

TEST_F(CloudFileWrite, MissingFolder_FailsAndLeavesNothing) {
  auto written = write_file_bytes(folder_ / "no" / "such" / "scan.ply", "x");
  ASSERT_FALSE(written);
  EXPECT_EQ(written.error(), CloudIoError::cannot_open_file);
  EXPECT_EQ(entries(), 0u);
}

}  // namespace
}  // namespace ldoem::cloud
