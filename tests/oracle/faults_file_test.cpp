// numerics_sweep --faults-file (faults_file.hpp): one line per fault with its case's bytes, the
// lines already in the file counted against the cap.
#include "faults_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace ldoem::oracle {
namespace {

std::vector<std::string> lines_of(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::filesystem::path scratch_file(const char* name) {
  const auto path = std::filesystem::temp_directory_path() / (std::string(name) + "." + std::to_string(::getpid()));
  std::filesystem::remove(path);
  return path;
}

TEST(FaultsFile, OneLinePerFault_CasterKindHexWhat) {
  const auto path = scratch_file("faults_file_format");
  Stats one;
  one.case_faults = {"moving range: skipped object 0 (triangle, part 1)", "embree wrong_object: object 0 hit at 65536"};
  {
    FaultsFile file(path.string());
    ASSERT_TRUE(file.ok());
    file.add(one, "62c9");
    file.add(one, "20f1");
    EXPECT_EQ(file.written(), 4u);
    EXPECT_EQ(file.dropped(), 0u);
  }
  EXPECT_EQ(lines_of(path), (std::vector<std::string>{"moving range 62c9 skipped object 0 (triangle, part 1)",
                                                      "embree wrong_object 62c9 object 0 hit at 65536",
                                                      "moving range 20f1 skipped object 0 (triangle, part 1)",
                                                      "embree wrong_object 20f1 object 0 hit at 65536"}));
  std::filesystem::remove(path);
}

TEST(FaultsFile, AppendsAndStopsAtTheCap_CountingLinesAlreadyThere) {
  const auto path = scratch_file("faults_file_cap");
  {
    std::ofstream earlier(path);
    for (std::uint64_t i = 0; i + 1 < FaultsFile::kMaxLines; ++i) earlier << "embree range aa earlier run\n";
  }
  Stats one;
  one.case_faults = {"moving missed: a", "moving missed: b", "moving missed: c"};
  FaultsFile file(path.string());
  file.add(one, "bb");
  EXPECT_EQ(file.written(), 1u);
  EXPECT_EQ(file.dropped(), 2u);
  const auto lines = lines_of(path);
  ASSERT_EQ(lines.size(), FaultsFile::kMaxLines);
  EXPECT_EQ(lines.back(), "moving missed bb a");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ldoem::oracle
