// TRANS_ROTATE timing and the head's spin-up (lead decision 4, D7), DO_RESET (lead decision 2,
// D3), and what a reset or a closed connection does to a held reply.
#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::control::test {
namespace {

TEST(TransRotate, ReplyIsSentExactlyWhenTheHeadReachesSpeed) {
  Bench bench;
  bench.head.duration = SimTime(1'234'567'891);
  bench.advance_to(SimTime(5ms));
  EXPECT_TRUE(bench.request(kTcp1, "TRANS_ROTATE 0000").empty());
  bench.advance_to(SimTime(5ms) + bench.head.duration - SimTime(1));
  EXPECT_TRUE(bench.sent_to(kTcp1, TelegramKind::reply).empty()) << bench.unit.dump(bench.now);
  bench.advance_by(SimTime(1));
  const auto replies = bench.sent_to(kTcp1, TelegramKind::reply);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].text(), "TRANS_ROTATE reply 0000 0002");
  EXPECT_EQ(replies[0].at, SimTime(5ms) + bench.head.duration);
  ASSERT_EQ(bench.head.asked.size(), 1u);
  EXPECT_EQ(bench.head.asked[0], std::make_pair(0.0, 10.0));  // from stopped to the flash speed
}

TEST(TransRotate, NewSpeedWhileRotating_AsksTheHeadFromTheCurrentSpeed) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 000a");
  bench.advance_by(2s);
  bench.request(kTcp1, "TRANS_ROTATE 0014");
  ASSERT_EQ(bench.head.asked.size(), 2u);
  EXPECT_EQ(bench.head.asked[1], std::make_pair(10.0, 20.0));
  EXPECT_EQ(bench.reply_text(kTcp2, "GET_STATUS"), "GET_STATUS reply 0000 0042");
  bench.advance_by(2s);
  EXPECT_EQ(bench.sent_to(kTcp1, TelegramKind::reply).back().text(), "TRANS_ROTATE reply 0000 0002");
  EXPECT_EQ(bench.unit.state().head.speed_hz, 20);
}

TEST(TransRotate, ReservedAndTooHighSpeeds_AreOutOfRange) {
  for (const char* request : {"TRANS_ROTATE 0001", "TRANS_ROTATE 0004", "TRANS_ROTATE 0015", "TRANS_ROTATE ffff"}) {
    Bench bench;
    EXPECT_EQ(bench.reply_text(kTcp1, request), "SERVICE_FAILURE 0403 0004") << request;
    EXPECT_EQ(bench.unit.state().mode, DeviceMode::idle);
  }
}

TEST(TransRotate, OtherConnectionsSeeSpinningUpUntilTheReply) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(1s);
  EXPECT_EQ(bench.reply_text(kTcp2, "TRANS_ROTATE 0000"), "SERVICE_FAILURE 0403 0003");
  EXPECT_EQ(bench.reply_text(kTcp2, "TRANS_IDLE"), "SERVICE_FAILURE 0402 0003");
  bench.advance_by(1s);
  // Only the connection that asked gets the held reply.
  EXPECT_EQ(bench.sent_to(kTcp1, TelegramKind::reply).size(), 1u);
  EXPECT_EQ(bench.sent_to(kTcp2, TelegramKind::reply).size(), 2u);
}

TEST(TransRotate, DoResetDuringSpinUp_AbortsItAndTheHeldReplyIsNeverSent) {
  for (const char* reset : {"DO_RESET 0000", "DO_RESET 0001", "DO_RESET 0002"}) {
    Bench bench;
    bench.request(kTcp1, "TRANS_ROTATE 0000");
    bench.advance_by(1s);
    EXPECT_EQ(bench.reply_text(kTcp1, reset), std::string("DO_RESET reply ") + std::string(reset).substr(9));
    bench.advance_by(10s);
    EXPECT_EQ(bench.sent_to(kTcp1, TelegramKind::reply).size(), 1u) << reset;
    EXPECT_EQ(bench.unit.state().mode, DeviceMode::idle) << reset;
    EXPECT_EQ(bench.unit.state().head.speed_hz, 0) << reset;
  }
}

TEST(TransRotate, ApdResetDuringSpinUp_ChangesNothing) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(1s);
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0010"), "DO_RESET reply 0010");
  bench.advance_by(1s);
  EXPECT_EQ(bench.sent_to(kTcp1, TelegramKind::reply).back().text(), "TRANS_ROTATE reply 0000 0002");
}

TEST(TransRotate, ConnectionClosedDuringSpinUp_HeadStillReachesSpeed) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.close(kTcp1);
  bench.advance_by(3s);
  EXPECT_TRUE(bench.log.empty());
  EXPECT_EQ(bench.reply_text(kTcp2, "GET_STATUS"), "GET_STATUS reply 0000 0002");
}

TEST(TransMeasure, RefusalKeepsRotateAndReportsTheCode) {
  Bench bench;
  // One sector over the whole turn at 0.25 deg, 10 Hz: max 14400 Hz is allowed, mean is not.
  bench.request(kTcp1, "SET_FUNCTION 0000 0003 1680 0000");
  bench.request(kTcp1, "SET_FUNCTION 0001 0000 0000 0000");
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(2s);
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_MEASURE"), "TRANS_MEASURE reply 0000 0002 0002");
  EXPECT_EQ(bench.unit.state().mode, DeviceMode::rotate);
}

TEST(TransMeasure, UsesTheActualHeadSpeed) {
  Bench bench;  // D4 table at 0.25 deg: fine at 10 Hz, max pulse too high at 11 Hz
  bench.request(kTcp1, "TRANS_ROTATE 000b");
  bench.advance_by(2s);
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_MEASURE"), "TRANS_MEASURE reply 0000 0002 0001");
}

TEST(TransMeasure, EachRefusalCodeReachesTheHost) {
  struct Case {
    std::vector<const char*> setup;
    const char* reply;
  };
  const Case cases[] = {
      {{"SET_CONFIG 0010 0001 000a 0002"}, "TRANS_MEASURE reply 0000 0002 0001"},
      {{"SET_FUNCTION 0000 0001 0870 0000"}, "TRANS_MEASURE reply 0000 0002 0003"},
      {{"SET_FUNCTION 0000 0003 0871 0000"}, "TRANS_MEASURE reply 0000 0002 0004"},
      {{"SET_FUNCTION 0001 0001 0960 0000"}, "TRANS_MEASURE reply 0000 0002 0002"},
      {{}, "TRANS_MEASURE reply 0000 0003 0000"},
  };
  for (const Case& c : cases) {
    Bench bench;
    for (const char* setup : c.setup) bench.request(kTcp1, setup);
    bench.request(kTcp1, "TRANS_ROTATE 0000");
    bench.advance_by(2s);
    EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_MEASURE"), c.reply) << bench.unit.dump(bench.now);
  }
}

TEST(DoReset, FullReset_EqualsThePowerUpState) {
  Bench bench;
  // Change everything a reset must undo: mode, head, stream, clock, signals, RAM-only sectors.
  bench.request(kTcp1, "SET_SIGNAL 0013");
  bench.request(kTcp1, "SET_TIME_ABS 1234");
  bench.request(kTcp1, "SET_FUNCTION 0002 0001 1680 0000");
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(3s);
  ASSERT_FALSE(bench.sent_to(kTcp1, TelegramKind::profile).empty());
  for (const char* level : {"DO_RESET 0000", "DO_RESET 0001"}) {
    bench.request(kTcp1, level);
    ControlUnit::Setup setup;
    setup.power_up_time = bench.now;
    Bench fresh(setup);
    EXPECT_EQ(bench.unit.state(), fresh.unit.state())
        << "after " << level << ":\n" << bench.unit.dump(bench.now) << "power-up:\n" << fresh.unit.dump(bench.now);
    bench.enter_measure();
    bench.request(kTcp1, "GET_PROFILE 0000 39ff");
    bench.advance_by(1s);
  }
}

TEST(DoReset, FullReset_KeepsFlashAndRestartsTheRevolutionCount) {
  Bench bench;
  bench.request(kTcp1, "SET_FUNCTION 0001 0001 0e10 0001");  // flash: same as D4
  bench.request(kTcp1, "SET_FUNCTION 0000 0003 0800 0001");  // flash: s0 to 128 deg
  bench.request(kTcp1, "SET_FUNCTION 0000 0003 0870 0000");  // RAM only: back to 135 deg
  bench.request(kTcp1, "DO_RESET 0000");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0800");
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(1s);
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 1u);
  EXPECT_EQ(profiles[0].profile_count, 1);  // D3: from 1 after power-up (request at the epoch)
}

TEST(DoReset, HaltToIdle_KeepsRamConfigurationClockAndSignals) {
  Bench bench;
  bench.request(kTcp1, "SET_FUNCTION 0000 0003 0800 0000");  // RAM only
  bench.request(kTcp1, "SET_SIGNAL 0003");
  bench.request(kTcp1, "SET_TIME_ABS 1000");
  bench.enter_measure();
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(bench.unit.state().mode, DeviceMode::idle);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0800");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_SIGNAL"), "GET_SIGNAL reply 0003");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_SYNC_CLOCK"), "GET_SYNC_CLOCK reply 17d0");  // 0x1000 + 2000 ms
}

TEST(DoReset, ApdLevel_ChangesNothing) {
  Bench bench;
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  const DeviceState before = bench.unit.state();
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0010"), "DO_RESET reply 0010");
  EXPECT_EQ(bench.unit.state(), before);
}

TEST(DoReset, ReservedLevels_AreOutOfRange) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0003"), "SERVICE_FAILURE 0401 0004");
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0011"), "SERVICE_FAILURE 0401 0004");
}

TEST(PowerUp, IsIdleWithTheD4Configuration) {
  Bench bench;
  EXPECT_EQ(bench.unit.state(), power_up_state(SimTime{}, factory_config()));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_CONFIG 0010"), "GET_CONFIG reply 0010 0001 000a 0004");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0870");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0001"), "GET_FUNCTION reply 0001 0001 0e10");
}

}  // namespace
}  // namespace ldoem::control::test
