// GET_PROFILE streams in simulated time: cadence, content, counters, skipping and the order of
// telegrams (spec 3.5, D3, D10, lead decision 5).
#include <gtest/gtest.h>

#include "control_test_support.hpp"
#include "ldoem/control/revolution_timing.hpp"

namespace ldoem::control::test {
namespace {

// Global config at `step` ticks, flash speed `speed_hz`, then IDLE -> ROTATE -> MEASURE. The
// head epoch (revolution 0 starts) is at t = 2 s, and now is left there.
void measure_at(Bench& bench, std::uint16_t speed_hz, std::uint16_t step) {
  const protocol::Request set_global = protocol::SetConfig{protocol::GlobalConfig{1, speed_hz, step, false}};
  ASSERT_EQ(bench.request(kTcp1, set_global).at(0).text(), "SET_CONFIG reply 0000");
  bench.enter_measure();
  ASSERT_EQ(bench.now, SimTime(2s));
}

class Cadence : public ::testing::TestWithParam<std::uint16_t> {};

TEST_P(Cadence, OneProfilePerRevolutionWithExactTimestamps) {
  const std::uint16_t speed_hz = GetParam();
  const SimTime period = SimTime(1'000'000'000 / speed_hz);
  Bench bench;
  measure_at(bench, speed_hz, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(10s);

  const auto sent = bench.sent_to(kTcp1, TelegramKind::profile);
  const auto profiles = bench.profiles_to(kTcp1);
  // The profile of revolution k is complete at its last point, 1.625 turns after revolution k
  // starts (sector 0 starts at 3608 ticks and the turn it covers ends at 3608 + 5752 = 9360).
  ASSERT_EQ(profiles.size(), 10u * speed_hz - 1u);
  EXPECT_EQ(sent[0].at, SimTime(2s) + period * 13 / 8);
  const std::uint16_t period_ms = static_cast<std::uint16_t>(1000 / speed_hz);
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    const protocol::Profile& profile = profiles[i];
    EXPECT_EQ(profile.profile_sent, i + 1);
    EXPECT_EQ(profile.profile_count, i + 1);
    EXPECT_EQ(sent[i].at - sent[0].at, period * static_cast<std::int64_t>(i));
    ASSERT_EQ(profile.sectors.size(), 2u);
    if (i > 0) {
      EXPECT_EQ(static_cast<std::uint16_t>(profile.sectors[0].t_start_ms - profiles[i - 1].sectors[0].t_start_ms),
                period_ms);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Speeds, Cadence, ::testing::Values(5, 10, 20));

TEST(ProfileContent, SectorBlocksFollowTheD4TableAt10Hz) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0001 3dff");
  bench.advance_by(1s);
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 1u);
  const protocol::Profile& profile = profiles[0];
  EXPECT_EQ(profile.format, 0x3DFF);
  EXPECT_EQ(profile.layer, 0);
  EXPECT_EQ(profile.status.status.to_byte(), 0x03);  // MEASURE, motor OK
  ASSERT_EQ(profile.sectors.size(), 2u);
  const protocol::SectorBlock& s0 = profile.sectors[0];
  EXPECT_EQ(s0.sector_num, 0);
  EXPECT_EQ(s0.dir_step_ticks, 8);
  EXPECT_EQ(s0.start_dir_ticks, 3608);
  EXPECT_EQ(s0.end_dir_ticks, 2160);
  ASSERT_EQ(s0.points.size(), 540u);
  EXPECT_EQ(s0.points[0].distance_q8_m, 256 + 3608);
  EXPECT_EQ(s0.points[268].distance_q8_m, 256 + 5760 - 8);
  EXPECT_EQ(s0.points[269].distance_q8_m, 256 + 0);  // through 0 deg into the next revolution
  EXPECT_EQ(s0.points[539].distance_q8_m, 256 + 2160);
  EXPECT_EQ(s0.points[0].echo, 1);  // the fake's echo is the revolution number
  // Clock 2000 ms at the epoch; 100 ms per revolution: 3608/5760 -> 62.6 ms, 7920/5760 -> 137.5.
  EXPECT_EQ(s0.t_start_ms, 2062);
  EXPECT_EQ(s0.t_end_ms, 2137);
  const protocol::SectorBlock& s1 = profile.sectors[1];
  EXPECT_EQ(s1.sector_num, 1);
  EXPECT_TRUE(s1.points.empty());  // D3: a non-measuring block has POINTNUM 0
  EXPECT_EQ(s1.start_dir_ticks, 2168);
  EXPECT_EQ(s1.end_dir_ticks, 3600);
  EXPECT_EQ(s1.t_start_ms, 2137);
  EXPECT_EQ(s1.t_end_ms, 2162);
}

TEST(ProfileContent, BeamsAreMeasuredAtTheirOwnTimeAndAngle) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(1s);
  ASSERT_EQ(bench.source.calls.size(), 1u);
  const auto& call = bench.source.calls[0];
  EXPECT_EQ(call.revolution, 1u);
  ASSERT_EQ(call.beams.size(), 540u);
  EXPECT_EQ(call.beams[0].angle_ticks, 3608);
  EXPECT_EQ(call.beams[0].beam_index, 3608u);
  EXPECT_EQ(call.beams[0].time, SimTime(2s) + SimTime(100ms) * 3608 / 5760);
  EXPECT_EQ(call.beams[269].angle_ticks, 0);
  EXPECT_EQ(call.beams[269].time, SimTime(2s) + SimTime(100ms));
}

TEST(ProfileStream, FirstProfileIsTheFirstRevolutionStartingAfterTheRequest) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.advance_by(SimTime(250ms));  // revolution 2 is running; revolution 3 starts at 2.3 s
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(1s);
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 1u);
  EXPECT_EQ(profiles[0].profile_count, 4);  // revolution index 3, counted from 1
  EXPECT_EQ(profiles[0].profile_sent, 1);
}

TEST(ProfileStream, CountedRequest_StopsAfterNAndRestartsProfileSent) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0003 39ff");
  bench.advance_by(2s);
  auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 3u);
  EXPECT_EQ(profiles[2].profile_sent, 3);
  EXPECT_FALSE(bench.unit.state().revolution_timer.has_value());
  bench.request(kTcp1, "GET_PROFILE 0002 39ff");
  bench.advance_by(2s);
  profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 5u);
  EXPECT_EQ(profiles[3].profile_sent, 1);
  EXPECT_EQ(profiles[4].profile_sent, 2);
  EXPECT_GT(profiles[3].profile_count, profiles[2].profile_count);
}

TEST(ProfileStream, NewRequestReplacesTheStream) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(SimTime(450ms));
  const std::size_t before = bench.profiles_to(kTcp1).size();
  bench.request(kTcp1, "GET_PROFILE 0000 3dff");
  bench.advance_by(1s);
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_GT(profiles.size(), before);
  EXPECT_EQ(profiles[before].format, 0x3DFF);
  EXPECT_EQ(profiles[before].profile_sent, 1);
  EXPECT_EQ(bench.unit.state().streams.size(), 1u);
}

TEST(ProfileStream, ProfilesGoOnlyToTheConnectionThatAsked_MeasuredOncePerRevolution) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.request(kCan1, "GET_PROFILE 0000 3dff");
  bench.advance_by(SimTime(1s));
  const auto tcp = bench.profiles_to(kTcp1);
  const auto can = bench.profiles_to(kCan1);
  EXPECT_TRUE(bench.sent_to(kTcp2, TelegramKind::profile).empty());
  ASSERT_EQ(tcp.size(), can.size());
  EXPECT_EQ(bench.source.calls.size(), tcp.size());
  for (std::size_t i = 0; i < tcp.size(); ++i) {
    EXPECT_EQ(tcp[i].format, 0x39FF);
    EXPECT_EQ(can[i].format, 0x3DFF);
    EXPECT_EQ(tcp[i].profile_count, can[i].profile_count);
    EXPECT_EQ(tcp[i].sectors[0].points[5].distance_q8_m, can[i].sectors[0].points[5].distance_q8_m);
  }
}

TEST(ProfileStream, BusyTransport_SkipsRevolutionsAndCountsThem) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(SimTime(200ms));  // profile of revolution 0 sent at 2.1625 s
  bench.transport.busy_connections.insert(kTcp1);
  bench.advance_by(SimTime(300ms));  // revolutions 1, 2, 3 are due while busy
  bench.transport.busy_connections.clear();
  bench.advance_by(SimTime(200ms));
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 3u);
  EXPECT_EQ(profiles[0].profile_count, 1);
  EXPECT_EQ(profiles[1].profile_count, 5);  // PROFILECOUNT jumps (D10)
  EXPECT_EQ(profiles[2].profile_count, 6);
  EXPECT_EQ(profiles[0].profile_sent, 1);
  EXPECT_EQ(profiles[1].profile_sent, 2);  // PROFILESENT stays consecutive
  EXPECT_EQ(profiles[2].profile_sent, 3);
  EXPECT_EQ(bench.unit.diagnostics().skipped_profiles, 3u);
}

TEST(ProfileStream, LateTimer_SendsOnlyTheNewestCompleteRevolution) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(SimTime(200ms));  // revolution 0 sent at 2.1625 s
  // Revolution k is complete at 2 s + k * 100 ms + 162.5 ms: 1..5 are complete at 2.75 s.
  bench.advance_late_to(SimTime(2s) + SimTime(750ms));
  auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 2u);
  EXPECT_EQ(profiles[1].profile_count, 6);  // revolution index 5
  EXPECT_EQ(profiles[1].profile_sent, 2);
  EXPECT_EQ(bench.unit.diagnostics().skipped_profiles, 4u);  // 1..4
  bench.advance_by(SimTime(100ms));  // back on the grid: revolution 6 at 2.7625 s
  profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 3u);
  EXPECT_EQ(profiles[2].profile_count, 7);
}

TEST(ProfileStream, BusyConnectionDoesNotHoldBackAnother) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.request(kTcp2, "GET_PROFILE 0000 39ff");
  bench.transport.busy_connections.insert(kTcp1);
  bench.advance_by(1s);
  EXPECT_TRUE(bench.profiles_to(kTcp1).empty());
  EXPECT_EQ(bench.profiles_to(kTcp2).size(), 9u);
}

// D10: a request that ends a stream stops it before its reply; no profile follows the reply.
void expect_reply_is_last(const Bench& bench, ConnectionId connection, std::string_view reply_text) {
  ASSERT_FALSE(bench.log.empty());
  std::vector<Sent> to_connection;
  for (const Sent& sent : bench.log) {
    if (sent.telegram.to == connection) to_connection.push_back(sent);
  }
  ASSERT_FALSE(to_connection.empty());
  EXPECT_EQ(to_connection.back().text(), reply_text);
  EXPECT_EQ(to_connection.back().telegram.kind, TelegramKind::reply);
}

TEST(StreamEnd, CancelProfile_NoProfileFollowsTheReply) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_to(SimTime(2s) + SimTime(1'162'500'000));  // exactly when a profile is due
  bench.request(kTcp1, "CANCEL_PROFILE");
  bench.advance_by(3s);
  expect_reply_is_last(bench, kTcp1, "CANCEL_PROFILE reply 0000 0003");
  EXPECT_EQ(bench.unit.state().mode, DeviceMode::measure);
}

TEST(StreamEnd, TransRotateSameSpeed_NoProfileFollowsTheReply) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(SimTime(730ms));
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(3s);
  expect_reply_is_last(bench, kTcp1, "TRANS_ROTATE reply 0000 0002");
}

TEST(StreamEnd, TransRotateNewSpeed_NoProfileBeforeOrAfterTheHeldReply) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(SimTime(730ms));
  const std::size_t profiles_before = bench.profiles_to(kTcp1).size();
  bench.request(kTcp1, "TRANS_ROTATE 0005");
  bench.advance_by(5s);
  EXPECT_EQ(bench.profiles_to(kTcp1).size(), profiles_before);
  expect_reply_is_last(bench, kTcp1, "TRANS_ROTATE reply 0000 0002");
}

TEST(StreamEnd, DoReset_NoProfileFollowsTheReply) {
  for (const char* reset : {"DO_RESET 0000", "DO_RESET 0001", "DO_RESET 0002"}) {
    Bench bench;
    measure_at(bench, 10, 8);
    bench.request(kTcp1, "GET_PROFILE 0000 39ff");
    bench.advance_by(SimTime(730ms));
    const auto reply = bench.request(kTcp1, reset);
    bench.advance_by(3s);
    expect_reply_is_last(bench, kTcp1, reply.at(0).text());
  }
}

TEST(StreamEnd, ConnectionClosed_StopsOnlyItsStream) {
  Bench bench;
  measure_at(bench, 10, 8);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.request(kTcp2, "GET_PROFILE 0000 39ff");
  bench.advance_by(SimTime(500ms));
  const std::size_t tcp1_before = bench.profiles_to(kTcp1).size();
  bench.close(kTcp1);
  bench.advance_by(SimTime(500ms));
  EXPECT_EQ(bench.profiles_to(kTcp1).size(), tcp1_before);
  EXPECT_EQ(bench.profiles_to(kTcp2).size(), 9u);
}

TEST(ProfileSize, OverTheTelegramLimit_IsRefusedOnTcpAndSerialButNotCan) {
  Bench bench;
  measure_at(bench, 5, 2);  // 0.125 deg at 5 Hz: 2160 points in sector 0
  // 0x3DFF: 12 + (14 + 4 * 2160) + 14 + 4 = 8684 bytes > 5816 (D3).
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_PROFILE 0000 3dff"), "SERVICE_FAILURE 0301 0004");
  EXPECT_EQ(bench.reply_text(kSerial1, "GET_PROFILE 0000 3dff"), "SERVICE_FAILURE 0301 0004");
  EXPECT_EQ(bench.reply_text(kCan1, "GET_PROFILE 0001 3dff"), "");
  // 0x39FF: 12 + (14 + 2 * 2160) + 14 + 4 = 4364 bytes fits.
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_PROFILE 0001 39ff"), "");
  bench.advance_by(1s);
  ASSERT_EQ(bench.sent_to(kCan1, TelegramKind::profile).size(), 1u);
  EXPECT_EQ(bench.sent_to(kCan1, TelegramKind::profile)[0].telegram.payload.size(), 8684u);
  ASSERT_EQ(bench.sent_to(kTcp1, TelegramKind::profile).size(), 1u);
  EXPECT_EQ(bench.sent_to(kTcp1, TelegramKind::profile)[0].telegram.payload.size(), 4364u);
}

TEST(ProfileFormat, UnpublishedBits_AreOutOfRange) {
  Bench bench;
  measure_at(bench, 10, 8);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_PROFILE 0000 79ff"), "SERVICE_FAILURE 0301 0004");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_PROFILE 0000 b9ff"), "SERVICE_FAILURE 0301 0004");
  EXPECT_TRUE(bench.unit.state().streams.empty());
}

TEST(ProfileClock, TimestampsWrapAt65536Ms) {
  Bench bench;
  const protocol::Request set_global = protocol::SetConfig{protocol::GlobalConfig{1, 10, 8, false}};
  bench.request(kTcp1, set_global);
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(2s);
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_TIME_ABS ffd0"), "SET_TIME_ABS reply ffd0");  // 65488 ms
  bench.request(kTcp1, "TRANS_MEASURE");
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(1s);
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 1u);
  EXPECT_EQ(profiles[0].sectors[0].t_start_ms, 14);  // 65488 + 62 = 65550 -> 14
  EXPECT_EQ(profiles[0].sectors[1].t_end_ms, 114);   // 65488 + 162 = 65650 -> 114
}

TEST(RevolutionTiming, GridIsExactAndDoesNotDrift) {
  const SimTime epoch(7);
  // 6 Hz does not divide a second in whole nanoseconds; times are floored from the epoch.
  EXPECT_EQ(revolution_time(epoch, 6, 6, 0), epoch + SimTime(1s));
  EXPECT_EQ(revolution_time(epoch, 6, 1, 0), epoch + SimTime(166'666'666));
  EXPECT_EQ(revolution_time(epoch, 6, 6'000'000, 2880), epoch + SimTime(1'000'000s) + SimTime(83'333'333));
  EXPECT_EQ(first_revolution_starting_at_or_after(epoch, 6, epoch), 0u);
  EXPECT_EQ(first_revolution_starting_at_or_after(epoch, 6, epoch + SimTime(1)), 1u);
  EXPECT_EQ(first_revolution_starting_at_or_after(epoch, 6, epoch + SimTime(166'666'666)), 1u);
  EXPECT_EQ(first_revolution_starting_at_or_after(epoch, 6, epoch + SimTime(166'666'667)), 2u);
  EXPECT_EQ(first_revolution_starting_at_or_after(epoch, 6, epoch - SimTime(1s)), 0u);
}

}  // namespace
}  // namespace ldoem::control::test
