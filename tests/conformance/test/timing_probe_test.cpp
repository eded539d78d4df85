// timing_probe: the verdict on whether the machine could keep time (pure), the summary line
// CI reads, and the probe itself seeing a stall it is shown.
#include <gtest/gtest.h>

#include <ctime>

#include "timing_probe.hpp"

namespace ldoem::conformance {
namespace {

ProbeSummary quiet() {
  ProbeSummary probe;
  probe.wakeups = 1900;
  probe.p50_ms = 0.06;
  probe.p99_ms = 0.4;
  probe.max_ms = 2.1;
  probe.run_delay_ms = 3;
  probe.window_ms = 1900;
  return probe;
}

TEST(TimingProbe, QuietMachine_CanJudge) { EXPECT_EQ(machine_busy(quiet(), 470), std::nullopt); }

TEST(TimingProbe, OneStallOfHalfTheTolerance_IsBusy) {
  ProbeSummary probe = quiet();
  probe.max_ms = 240;
  const auto busy = machine_busy(probe, 470);
  ASSERT_TRUE(busy);
  EXPECT_EQ(busy->rfind("machine busy: p99 wake-up 0.4 ms, max 240.0 ms", 0), 0u) << *busy;
  probe.max_ms = 230;
  EXPECT_EQ(machine_busy(probe, 470), std::nullopt);
}

TEST(TimingProbe, CommonStallsOfATenthOfTheTolerance_AreBusy) {
  ProbeSummary probe = quiet();
  probe.p99_ms = 37;
  probe.max_ms = 90;
  const auto busy = machine_busy(probe, 300);
  ASSERT_TRUE(busy);
  EXPECT_NE(busy->find("p99 wake-up 37.0 ms"), std::string::npos) << *busy;
  EXPECT_EQ(machine_busy(probe, 400), std::nullopt);  // 37 < 40 and 90 < 200
}

TEST(TimingProbe, RunDelayOfATenthOfTheWindow_IsBusy) {
  ProbeSummary probe = quiet();
  probe.run_delay_ms = 190;
  const auto busy = machine_busy(probe, 470);
  ASSERT_TRUE(busy);
  EXPECT_NE(busy->find("run delay 190.0 ms (10.0 % of 1900.0 ms)"), std::string::npos) << *busy;
  probe.run_delay_ms = 189;
  EXPECT_EQ(machine_busy(probe, 470), std::nullopt);
}

TEST(TimingProbe, Summarize_NearestRankPercentiles) {
  std::vector<double> lateness;
  for (int i = 1; i <= 200; ++i) lateness.push_back(i);  // 1..200 ms, shuffled order irrelevant
  std::swap(lateness.front(), lateness.back());
  const ProbeSummary probe = summarize(lateness, 12.5, 1000);
  EXPECT_EQ(probe.wakeups, 200u);
  EXPECT_EQ(probe.p50_ms, 100);
  EXPECT_EQ(probe.p99_ms, 198);
  EXPECT_EQ(probe.max_ms, 200);
  EXPECT_EQ(probe.run_delay_ms, 12.5);
  std::vector<double> none;
  EXPECT_EQ(summarize(none, 0, 0).max_ms, 0);
}

TEST(TimingProbe, SummaryLine_KeepsPassedFailedFirst) {
  EXPECT_EQ(summary_line(38, 1, 2), "38 passed, 1 failed, 2 inconclusive");
  EXPECT_EQ(summary_line(0, 1, 0), "0 passed, 1 failed, 0 inconclusive");
}

// The probe itself: it runs over its window, wakes at most once per millisecond (the next tick
// is armed 1 ms after each wake-up), and a second stop() reports the same window.
TEST(TimingProbe, Probe_CountsWakeUpsOverItsWindow) {
  SchedulingProbe probe;
  timespec pause{0, 50'000'000};  // 50 ms
  nanosleep(&pause, nullptr);
  const ProbeSummary summary = probe.stop();
  EXPECT_GE(summary.window_ms, 50);
  EXPECT_GT(summary.wakeups, 0u);
  EXPECT_LE(summary.wakeups, static_cast<std::size_t>(summary.window_ms) + 1);  // one per ms at most
  EXPECT_GE(summary.max_ms, summary.p99_ms);
  EXPECT_EQ(probe.stop().wakeups, summary.wakeups);  // stop twice: the same window
}

}  // namespace
}  // namespace ldoem::conformance
