// design.md: the driver's correctness must not lean on the simulated device's code. This test
// reads every file under driver/ and fails on any mention of it, even in a comment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

// `#include.*emulator/` on any line (std::regex is avoided: GCC 12 warns inside it under ASan).
bool includes_from_emulator(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t include = line.find("#include");
    if (include != std::string::npos && line.find("emulator/", include) != std::string::npos) {
      return true;
    }
  }
  return false;
}

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

TEST(DriverSources, NeverNameTheEmulator) {
  const fs::path root = fs::path(LDOEM_SOURCE_DIR) / "driver";
  ASSERT_TRUE(fs::is_directory(root)) << root;
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) {
      continue;
    }
    ++files;
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    const std::string lower = lowercase(text);
    EXPECT_EQ(lower.find("emulator"), std::string::npos) << entry.path() << " names the emulator";
    EXPECT_EQ(lower.find("ldoem-emud"), std::string::npos) << entry.path() << " names ldoem-emud";
    EXPECT_FALSE(includes_from_emulator(text)) << entry.path() << " includes from emulator/";
  }
  EXPECT_GT(files, 10u);  // the walk really saw the driver's sources
}

}  // namespace
