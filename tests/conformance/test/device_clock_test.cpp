// device_clock: the device's timing judged from the profiles alone. The doctored streams here
// are the test double of a device whose clock slips: each one must fail, and a stream that
// skips revolutions honestly (PROFILECOUNT jumps, TSTART with it) must pass.
#include <gtest/gtest.h>

#include "device_clock.hpp"

namespace ldoem::conformance {
namespace {

namespace p = protocol;

// Profile `sent` of a stream at 10 Hz: revolution `count`, sector 0 measured from TSTART for
// 75 ms (270 deg of 360), sector 1 not measuring.
p::Profile profile(std::uint16_t sent, std::uint16_t count, std::uint16_t t_start, std::uint16_t span = 75) {
  p::Profile out;
  out.format = p::kFormatRange;
  out.profile_sent = sent;
  out.profile_count = count;
  p::SectorBlock measuring;
  measuring.sector_num = 0;
  measuring.t_start_ms = t_start;
  measuring.t_end_ms = static_cast<std::uint16_t>(t_start + span);
  measuring.points = {{1280, 0, 0}, {1280, 0, 0}};
  p::SectorBlock idle;
  idle.sector_num = 1;
  idle.t_start_ms = 0;  // a non-measuring sector's times are not judged
  out.sectors = {measuring, idle};
  return out;
}

std::optional<std::string> run(const std::vector<p::Profile>& stream, std::uint16_t hz = 10) {
  DeviceClockCheck check;
  check.set_speed_hz(hz);
  for (const p::Profile& item : stream) {
    if (auto verdict = check.next(item)) return verdict;
  }
  return std::nullopt;
}

TEST(DeviceClock, OneRevolutionPerProfile_Passes) {
  EXPECT_EQ(run({profile(1, 7, 1000), profile(2, 8, 1100), profile(3, 9, 1200)}), std::nullopt);
}

TEST(DeviceClock, TruncatedMilliseconds_PassWithinOneMillisecond) {
  // 6 Hz: 166.67 ms per revolution, TSTART truncated to whole ms.
  EXPECT_EQ(run({profile(1, 1, 0, 120), profile(2, 2, 166, 120), profile(3, 3, 333, 120), profile(4, 4, 500, 120)}, 6),
            std::nullopt);
}

TEST(DeviceClock, SkippedRevolutions_PassWhenCountedAndTimed) {
  DeviceClockCheck check;
  EXPECT_EQ(check.next(profile(1, 7, 1000)), std::nullopt);
  EXPECT_EQ(check.next(profile(2, 17, 2000)), std::nullopt);  // stopped 1 s: 10 revolutions later
  EXPECT_EQ(check.skipped_revolutions(), 9u);
}

TEST(DeviceClock, AcrossTheSixteenBitWrap_Passes) {
  EXPECT_EQ(run({profile(1, 65535, 65500), profile(2, 0, 64)}), std::nullopt);
}

TEST(DeviceClock, ClockRunningSlow_Fails) {
  // A device clock that slips 2 ms per revolution.
  const auto verdict = run({profile(1, 7, 1000), profile(2, 8, 1098)});
  ASSERT_TRUE(verdict);
  EXPECT_NE(verdict->find("TSTART advanced 98 ms"), std::string::npos) << *verdict;
  EXPECT_NE(verdict->find("expected 100 ms"), std::string::npos) << *verdict;
}

TEST(DeviceClock, SkipNotCounted_Fails) {
  // TSTART jumped three revolutions but PROFILECOUNT only one: a revolution vanished unseen.
  const auto verdict = run({profile(1, 7, 1000), profile(2, 8, 1300)});
  ASSERT_TRUE(verdict);
  EXPECT_NE(verdict->find("PROFILECOUNT advance of 1"), std::string::npos) << *verdict;
}

TEST(DeviceClock, CountedButClockStood_Fails) {
  // The counter says 10 revolutions passed, the clock says one: a clock that stopped with the process.
  const auto verdict = run({profile(1, 7, 1000), profile(2, 17, 1100)});
  ASSERT_TRUE(verdict);
  EXPECT_NE(verdict->find("expected 1000 ms"), std::string::npos) << *verdict;
}

TEST(DeviceClock, CounterStands_Fails) {
  const auto verdict = run({profile(1, 7, 1000), profile(2, 7, 1100)});
  ASSERT_TRUE(verdict);
  EXPECT_NE(verdict->find("PROFILECOUNT stayed 7"), std::string::npos) << *verdict;
}

TEST(DeviceClock, ProfileSentGap_Fails) {
  const auto verdict = run({profile(1, 7, 1000), profile(3, 8, 1100)});
  ASSERT_TRUE(verdict);
  EXPECT_NE(verdict->find("not consecutive"), std::string::npos) << *verdict;
}

TEST(DeviceClock, ProfileSentGapWhenTheLinkDroppedTelegrams_IsNotTheDevicesButTheClockStillIs) {
  DeviceClockCheck check;
  EXPECT_EQ(check.next(profile(1, 7, 1000)), std::nullopt);
  EXPECT_EQ(check.next(profile(3, 9, 1200), 1), std::nullopt);  // profile 2 lost on the link
  EXPECT_EQ(check.last_sent_step(), 2);
  EXPECT_TRUE(check.next(profile(6, 12, 1500), 1));     // 2 missing, 1 dropped: the device's gap
  EXPECT_TRUE(check.next(profile(7, 13, 1598), 5));     // a slipping clock fails all the same
}

TEST(DeviceClock, SweepLongerThanARevolution_Fails) {
  const auto verdict = run({profile(1, 7, 1000, 102)});
  ASSERT_TRUE(verdict);
  EXPECT_NE(verdict->find("longer than one revolution"), std::string::npos) << *verdict;
}

TEST(DeviceClock, WrongSpeed_Fails) {
  // 10 Hz revolutions judged as the 20 Hz the host configured.
  EXPECT_TRUE(run({profile(1, 7, 1000, 40), profile(2, 8, 1100, 40)}, 20));
}

TEST(DeviceClock, AfterStopJudging_NothingIsJudgedUntilTheNextStream) {
  DeviceClockCheck check;
  EXPECT_EQ(check.next(profile(1, 7, 1000)), std::nullopt);
  check.stop_judging();
  EXPECT_EQ(check.next(profile(2, 8, 1098)), std::nullopt);
  EXPECT_EQ(check.next(profile(3, 9, 1196)), std::nullopt);
  check.start_stream();
  EXPECT_EQ(check.next(profile(1, 20, 2000)), std::nullopt);
  EXPECT_TRUE(check.next(profile(2, 21, 2098)));
}

TEST(DeviceClock, NewStream_IsNotComparedWithTheOldOne) {
  DeviceClockCheck check;
  EXPECT_EQ(check.next(profile(1, 7, 1000)), std::nullopt);
  check.start_stream();
  EXPECT_EQ(check.next(profile(1, 30, 3333)), std::nullopt);
  p::Profile echo = profile(2, 31, 3433);
  echo.format = p::kFormatRangeEcho;  // a change of format is a new stream too
  echo.profile_sent = 1;
  EXPECT_EQ(check.next(echo), std::nullopt);
}

}  // namespace
}  // namespace ldoem::conformance
