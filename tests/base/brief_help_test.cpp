// base::brief_help: what every program's --help prints, taken from its --help-all text.
#include <gtest/gtest.h>

#include <sstream>

#include "ldoem/base/command_line.hpp"

namespace ldoem::base {
namespace {

const char* const kFull =
    "usage: tool --in FILE [--out FILE] [--a-rather-long-option-name VALUE] [--another-long-one VALUE] [--more]\n"
    "A long description that --help leaves out.\n"
    "\n"
    "Options:\n"
    "  --in FILE       the input, a file whose description the full text wraps at a width wider than a\n"
    "                  terminal's, continued here\n"
    "  --out FILE      the output [stdout]\n"
    "  --verbose, -v   say more\n"
    "  --quiet         say less\n"
    "\n"
    "Exit status: 0 done.\n";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

TEST(BriefHelp, TheUsageLineThePurposeTheNamedOptionsAndAPointer) {
  const std::string brief = brief_help("tool", kFull, "Turn FILE into another.", {"--out", "-v", "--in", "--absent"});
  const std::vector<std::string> lines = lines_of(brief);
  for (const std::string& line : lines) EXPECT_LE(line.size(), 80u) << line;
  ASSERT_GE(lines.size(), 8u);
  EXPECT_EQ(lines[0].rfind("usage: tool --in FILE", 0), 0u);
  EXPECT_EQ(lines[1].rfind("           ", 0), 0u) << "the usage line goes on under its first argument";
  EXPECT_EQ(lines[2], "Turn FILE into another.");
  // In the order asked for; a description is joined and wrapped again under its column.
  EXPECT_NE(brief.find("  --out FILE      the output [stdout]\n  --verbose, -v   say more\n  --in FILE       the input"),
            std::string::npos)
      << brief;
  EXPECT_NE(brief.find("\n                  "), std::string::npos) << brief;
  EXPECT_EQ(brief.find("--quiet"), std::string::npos);
  EXPECT_EQ(brief.find("--absent"), std::string::npos) << "an option the full text lacks is left out";
  EXPECT_EQ(brief.find("Exit status"), std::string::npos);
  EXPECT_EQ(lines.back(), "All options: tool --help-all; the manual: man tool");
}

TEST(UsageErrorLine, OneLineWithTheHint) {
  EXPECT_EQ(usage_error_line("tool", "--in: needs a value"), "tool: --in: needs a value (try --help)\n");
  EXPECT_EQ(usage_error_line("tool", "unknown option `-x` (try --help)"), "tool: unknown option `-x` (try --help)\n");
}

}  // namespace
}  // namespace ldoem::base
