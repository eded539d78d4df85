// ldoem-scan's outputs: every path checked before the scan with the operating system's reason,
// and all files written or none (output_files.hpp).
#include "ldoem/scan/output_files.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::scan {
namespace {

using test_support::TempDir;
using ::testing::HasSubstr;

// The names in FOLDER, temporaries (".NAME.XXXXXX") included.
std::vector<std::string> names_in(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(CheckOutputPath, AWritableFolder_PassesAndLeavesNothingBehind) {
  TempDir dir;
  EXPECT_TRUE(check_output_path(dir.path("scan.ply")).has_value());
  EXPECT_TRUE(names_in(dir.folder()).empty());
}

TEST(CheckOutputPath, AMissingFolder_NamesItWithTheSystemsReason) {
  TempDir dir;
  auto checked = check_output_path(dir.path("missing/scan.ply"));
  ASSERT_FALSE(checked.has_value());
  EXPECT_THAT(checked.error(), HasSubstr("missing"));
  EXPECT_THAT(checked.error(), HasSubstr("No such file or directory"));
}

TEST(CheckOutputPath, APathThatIsAFolder_IsRefused) {
  TempDir dir;
  std::filesystem::create_directory(dir.path("scan.ply"));
  auto checked = check_output_path(dir.path("scan.ply"));
  ASSERT_FALSE(checked.has_value());
  EXPECT_THAT(checked.error(), HasSubstr("is a folder"));
}

TEST(CheckOutputPath, AFolderThatIsAFile_IsRefused) {
  TempDir dir;
  dir.write("plain", "x");
  auto checked = check_output_path(dir.path("plain/scan.ply"));
  ASSERT_FALSE(checked.has_value());
  EXPECT_THAT(checked.error(), HasSubstr("is not a folder"));
}

TEST(WriteAllOrNone, AllWritable_WritesEveryFileWhole) {
  TempDir dir;
  auto written = write_all_or_none({{dir.path("a.ply"), "cloud"}, {dir.path("a.png"), "picture"}});
  ASSERT_TRUE(written.has_value()) << written.error();
  EXPECT_EQ(test_support::read_file(dir.path("a.ply")), "cloud");
  EXPECT_EQ(test_support::read_file(dir.path("a.png")), "picture");
  EXPECT_EQ(names_in(dir.folder()), (std::vector<std::string>{"a.ply", "a.png"}));
}

TEST(WriteAllOrNone, OneFileCannotBeWritten_WritesNoneAndRemovesTheTemporaries) {
  TempDir dir;
  dir.write("old.ply", "the previous scan");
  auto written = write_all_or_none({{dir.path("old.ply"), "new cloud"}, {dir.path("gone/a.png"), "picture"}});
  ASSERT_FALSE(written.has_value());
  EXPECT_THAT(written.error(), HasSubstr("gone/a.png"));
  EXPECT_THAT(written.error(), HasSubstr("No such file or directory"));
  EXPECT_EQ(test_support::read_file(dir.path("old.ply")), "the previous scan");
  EXPECT_EQ(names_in(dir.folder()), (std::vector<std::string>{"old.ply"}));
}

}  // namespace
}  // namespace ldoem::scan
