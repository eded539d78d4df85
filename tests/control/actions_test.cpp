// What the control unit tells the daemon besides telegrams (ports.hpp Actions): stale timers to
// cancel, a new head target, a new CAN configuration. The daemon never compares states, so each
// of these must come exactly when the state changes and never otherwise.
#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::control::test {
namespace {

using namespace std::chrono_literals;

TEST(CancelledTimers, CancelProfile_CancelsTheRevolutionTimer) {
  Bench bench;
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  ASSERT_EQ(bench.pending_timers(), 1u) << bench.unit.dump(bench.now);
  ASSERT_TRUE(bench.unit.state().revolution_timer.has_value());
  const TimerId revolution_timer = bench.unit.state().revolution_timer->timer;
  bench.request(kTcp1, "CANCEL_PROFILE");
  EXPECT_EQ(bench.cancelled_timers, std::vector<TimerId>{revolution_timer});
  EXPECT_EQ(bench.pending_timers(), 0u);
}

TEST(CancelledTimers, ClosingTheLastStreamsConnection_CancelsTheRevolutionTimer) {
  Bench bench;
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  const TimerId revolution_timer = bench.unit.state().revolution_timer->timer;
  bench.close(kTcp1);
  EXPECT_EQ(bench.cancelled_timers, std::vector<TimerId>{revolution_timer});
  EXPECT_EQ(bench.pending_timers(), 0u);
}

TEST(CancelledTimers, ResetDuringSpinUp_CancelsTheSpinUpTimer) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  const TimerId spin_up_timer = bench.unit.state().spin_up->timer;
  bench.request(kTcp1, "DO_RESET 0000");
  EXPECT_EQ(bench.cancelled_timers, std::vector<TimerId>{spin_up_timer});
  EXPECT_EQ(bench.pending_timers(), 0u);
}

TEST(CancelledTimers, ATimerThatFires_IsNeverNamed) {
  Bench bench;
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0003 39ff");
  bench.advance_by(2s);
  EXPECT_EQ(bench.profiles_to(kTcp1).size(), 3u);
  EXPECT_TRUE(bench.cancelled_timers.empty());
}

TEST(HeadTarget, SpinUpAndStop_AreToldOnceEach) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 000a");
  EXPECT_EQ(bench.head_targets, std::vector<std::uint16_t>{10});
  bench.advance_by(3s);  // the spin-up completes: the same target, nothing new
  EXPECT_EQ(bench.head_targets, std::vector<std::uint16_t>{10});
  bench.request(kTcp1, "GET_STATUS");
  bench.request(kTcp1, "TRANS_IDLE");
  EXPECT_EQ(bench.head_targets, (std::vector<std::uint16_t>{10, 0}));
}

TEST(CanConfig, SetConfigKey2_IsToldWithTheNewPair_AndAnUnchangedOneIsNot) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_CONFIG 0002 0004 0700 0701 0000 0000"), "SET_CONFIG reply 0000");
  ASSERT_EQ(bench.can_configs.size(), 1u);
  EXPECT_EQ(bench.can_configs[0].request_id, 0x700);
  EXPECT_EQ(bench.can_configs[0].response_id, 0x701);
  bench.request(kTcp1, "SET_CONFIG 0002 0004 0700 0701 0000 0000");
  EXPECT_EQ(bench.can_configs.size(), 1u);
  bench.request(kTcp1, "SET_CONFIG 0002 0005 0600 0601 0000 0000");  // refused: nothing changes
  EXPECT_EQ(bench.can_configs.size(), 1u);
}

TEST(Measurement, IsToldTheRevolutionsStart) {
  Bench bench;
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(1s);
  ASSERT_EQ(bench.source.calls.size(), 1u);
  const auto& call = bench.source.calls[0];
  ASSERT_FALSE(call.beams.empty());
  // The first beam fires within the first turn of its revolution, and revolutions start on the
  // 100 ms grid (10 Hz) of the head's epoch.
  EXPECT_LE(call.revolution_start, call.beams.front().time);
  EXPECT_GT(call.revolution_start + SimTime(100ms), call.beams.front().time);
  EXPECT_EQ((call.revolution_start - bench.unit.state().head.epoch_start) % SimTime(100ms), SimTime::zero());
}

}  // namespace
}  // namespace ldoem::control::test
