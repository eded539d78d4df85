#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "ldoem/scan/progress_bar.hpp"

namespace ldoem::scan {
namespace {

using std::chrono::milliseconds;

ProgressBarOptions ten_wide() {
  ProgressBarOptions options;
  options.bar_width = 10;
  options.min_interval = milliseconds(100);
  return options;
}

TEST(ProgressBar, Render_ShowsBarPercentAndCount) {
  std::ostringstream out;
  const ProgressBar bar(out, true, ten_wide());
  EXPECT_EQ(bar.render(100, 240), "[====>     ] 42% layer 100/240");
  EXPECT_EQ(bar.render(0, 240), "[>         ] 0% layer 0/240");
  EXPECT_EQ(bar.render(240, 240), "[==========] 100% layer 240/240");
  EXPECT_EQ(bar.render(1999, 2000), "[=========>] 99% layer 1999/2000");
}

TEST(ProgressBar, Terminal_DrawsWithCarriageReturnAndEndsWithNewline) {
  std::ostringstream out;
  ProgressBar bar(out, true, ten_wide());
  bar.update(1, 2, milliseconds(0));
  bar.update(2, 2, milliseconds(1));
  bar.finish();
  EXPECT_EQ(out.str(), "\r[=====>    ] 50% layer 1/2\r[==========] 100% layer 2/2\n");
}

TEST(ProgressBar, UpdatesWithinInterval_AreSkippedButLastStepDrawn) {
  std::ostringstream out;
  ProgressBar bar(out, true, ten_wide());
  bar.update(1, 4, milliseconds(1000));
  bar.update(2, 4, milliseconds(1099));  // 99 ms later: skipped
  bar.update(3, 4, milliseconds(1100));  // 100 ms after the last draw: drawn
  bar.update(4, 4, milliseconds(1101));  // complete: always drawn
  const std::string text = out.str();
  EXPECT_EQ(text.find("2/4"), std::string::npos);
  EXPECT_NE(text.find("3/4"), std::string::npos);
  EXPECT_NE(text.find("4/4"), std::string::npos);
}

TEST(ProgressBar, NotTerminal_WritesOneWholeLinePerTenth) {
  std::ostringstream out;
  ProgressBar bar(out, false, ten_wide());
  for (std::uint64_t done = 0; done <= 40; ++done) bar.update(done, 40, milliseconds(500 * done));
  bar.finish();
  const std::string text = out.str();
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 11) << text;  // 0 %, 10 %, ..., 100 %
  EXPECT_NE(text.find("10% layer 4/40, 18s left\n"), std::string::npos) << text;
  EXPECT_NE(text.find("100% layer 40/40\n"), std::string::npos) << text;
}

TEST(ProgressBar, TimeLeft_IsTheMeanStepTimeTimesTheStepsLeft) {
  std::ostringstream out;
  ProgressBar bar(out, true, ten_wide());
  bar.update(0, 10, milliseconds(0));  // the first step: no estimate yet
  EXPECT_EQ(out.str(), "\r[>         ] 0% layer 0/10");
  bar.update(2, 10, milliseconds(30000));  // 15 s per layer, 8 to go: 2 minutes
  EXPECT_NE(out.str().find("20% layer 2/10, 2m00s left"), std::string::npos) << out.str();
}

TEST(ProgressBar, FormatTimeLeft_ReadsAsAPersonWouldSayIt) {
  EXPECT_EQ(format_time_left(std::chrono::seconds(0)), "0s");
  EXPECT_EQ(format_time_left(std::chrono::seconds(45)), "45s");
  EXPECT_EQ(format_time_left(std::chrono::seconds(65)), "1m05s");
  EXPECT_EQ(format_time_left(std::chrono::seconds(7380)), "2h03m");
  EXPECT_EQ(format_time_left(std::chrono::seconds(-3)), "0s");
}

TEST(ProgressBar, ShorterLine_BlanksLeftovers) {
  std::ostringstream out;
  ProgressBar bar(out, true, ten_wide());
  bar.update(1000, 1000, milliseconds(0));  // "[==========] 100% layer 1000/1000" (33 chars)
  out.str("");
  bar.update(5, 10, milliseconds(200));     // "[=====>    ] 50% layer 5/10" (27 chars) + 6 spaces
  EXPECT_EQ(out.str(), "\r[=====>    ] 50% layer 5/10      ");
}

TEST(ProgressBar, FinishTwice_WritesOneNewline) {
  std::ostringstream out;
  ProgressBar bar(out, true, ten_wide());
  bar.update(1, 1, milliseconds(0));
  bar.finish();
  bar.finish();
  bar.update(1, 1, milliseconds(1000));
  EXPECT_EQ(out.str(), "\r[==========] 100% layer 1/1\n");
}

TEST(ProgressBar, ZeroTotal_ShowsFull) {
  std::ostringstream out;
  const ProgressBar bar(out, true, ten_wide());
  EXPECT_EQ(bar.render(0, 0), "[==========] 100% layer 0/0");
}

}  // namespace
}  // namespace ldoem::scan
