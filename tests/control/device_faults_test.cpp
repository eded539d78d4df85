// D11 device faults: status nibbles, ERROR and what it answers, recovery, beam faults.
#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::control::test {
namespace {

constexpr SimTime kRevolutionAt10Hz = 100ms;

// IDLE -> MEASURE at 10 Hz with a stream running on kTcp1.
// Format 3fff (every field, direction and echo included) on CAN: over 5816 bytes, which TCP
// and serial refuse (D3).
void stream(Bench& bench) {
  bench.enter_measure();
  bench.request(kCan1, "GET_PROFILE 0000 3fff");
  bench.advance_by(250ms);
  ASSERT_FALSE(bench.profiles_to(kCan1).empty());
}

TEST(MotorFaults, StallWithoutHeadDynamics_StopsAtOnce_ErrorOneRevolutionLater) {
  Bench bench;
  stream(bench);
  const std::size_t profiles_before = bench.profiles_to(kCan1).size();
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::stall, false));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b3") << bench.unit.dump(bench.now);
  bench.advance_by(kRevolutionAt10Hz - 1ms);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b3");
  bench.advance_by(1ms);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
  bench.advance_by(2s);
  EXPECT_EQ(bench.profiles_to(kCan1).size(), profiles_before) << "the stream stops at the fault";
  EXPECT_EQ(bench.unit.state().head.speed_hz, 0);
}

// Found by the Python fault matrix (tcp-motor_stall-while_streaming): a stall triggered by the
// GET_PROFILE itself leaves MEASURE with the head at 0 Hz; the request then divided by the
// speed (SIGFPE, the daemon died). A stopped head turns no revolution: no stream, no profile.
TEST(MotorFaults, GetProfileWithTheHeadStalledStartsNoStreamAndTheDaemonLivesOn) {
  Bench bench;
  bench.enter_measure();
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::stall, false));
  ASSERT_EQ(bench.unit.state().head.speed_hz, 0);
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  bench.advance_by(2s);
  EXPECT_TRUE(bench.profiles_to(kTcp1).empty());
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
}

TEST(MotorFaults, StallWithHeadDynamics_CoastsThroughSpinTooLow) {
  Bench bench;
  stream(bench);
  // The fake head takes 2 s for any change: 0x4 and 0xB would coincide, so 0x4 is skipped and
  // ERROR comes one revolution after 0xB.
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::stall, true));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0003");
  bench.advance_by(2s);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b3");
  bench.advance_by(kRevolutionAt10Hz);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
}

// A head whose coast-down takes time proportional to the speed lost (1 s per 10 Hz).
class ProportionalHead final : public HeadModel {
 public:
  SimTime time_to_reach(double from_hz, double to_hz) const override {
    return std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(std::abs(from_hz - to_hz) / 10.0));
  }
};

TEST(MotorFaults, StallWithHeadDynamics_NibbleFourBelowNinetyPercent) {
  ProportionalHead head;
  AngleDerivedSource source;
  FakeTransportQuery transport;  // never busy
  ControlUnit unit({}, head, source);
  // 0 -> 10 Hz takes 1 s with this head.
  Actions spin = unit.handle_request(0s, kTcp1, telegram("TRANS_ROTATE 0000"), transport);
  ASSERT_EQ(spin.timers.size(), 1u);
  (void)unit.on_timer(1s, spin.timers[0].id, transport);
  Actions fault = unit.inject_motor_fault(2s, MotorFault::stall, true);
  // 10 -> 9 Hz in 0.1 s: nibble 0x4 at 2.1 s, ERROR one revolution later (2.2 s), 0xB at 3 s.
  ASSERT_EQ(fault.timers.size(), 1u);
  EXPECT_EQ(fault.timers[0].at, 2100ms);
  EXPECT_EQ(unit.status_byte().to_byte(), 0x02);
  Actions low = unit.on_timer(2100ms, fault.timers[0].id, transport);
  EXPECT_EQ(unit.status_byte().to_byte(), 0x42);
  ASSERT_EQ(low.timers.size(), 1u);
  EXPECT_EQ(low.timers[0].at, 2200ms);
  Actions error = unit.on_timer(2200ms, low.timers[0].id, transport);
  EXPECT_EQ(unit.status_byte().to_byte(), 0x44);
  ASSERT_EQ(error.timers.size(), 1u);
  EXPECT_EQ(error.timers[0].at, 3s);
  (void)unit.on_timer(3s, error.timers[0].id, transport);
  EXPECT_EQ(unit.status_byte().to_byte(), 0xB4);
}

TEST(MotorFaults, OverspeedNibbleNineThenError) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::overspeed, true));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0093");
  bench.advance_by(kRevolutionAt10Hz);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0094");
}

TEST(MotorFaults, EncoderErrorIsErrorAtOnce) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::encoder, false));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
}

TEST(MotorFaults, HeldTransRotateIsAnsweredWithError) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");  // waits 2 s for the head
  bench.advance_by(1s);
  const auto sent = bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::encoder, false));
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].text(), "TRANS_ROTATE reply 0000 00b4");
  bench.advance_by(3s);
  EXPECT_EQ(bench.sent_to(kTcp1, TelegramKind::reply).size(), 1u) << "answered once";
}

// L-faults-6: between a motor fault and ERROR (one revolution) the head cannot measure: a
// TRANS_MEASURE is refused with reason 3, as ERROR refuses it, from ROTATE and from MEASURE. A
// TRANS_ROTATE then tries to spin the failed motor: ERROR at once, its reply says so.
TEST(MotorFaults, TransMeasureWithinTheRevolutionAfterAStall_IsRefusedReasonThree) {
  Bench bench;
  bench.request(kTcp1, "TRANS_ROTATE 0000");
  bench.advance_by(bench.head.duration);
  ASSERT_EQ(bench.unit.state().mode, DeviceMode::rotate);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::stall, false));
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003") << bench.unit.dump(bench.now);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b2");
  bench.advance_by(kRevolutionAt10Hz);
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003");  // ERROR now
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b4");
}

TEST(MotorFaults, TransMeasureInMeasureAfterAnOverspeed_IsRefusedReasonThree) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::overspeed, false));
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_MEASURE"), "SERVICE_FAILURE 0404 0003");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0093");
}

TEST(MotorFaults, TransRotateWithinTheRevolutionAfterAStall_EntersErrorAndSaysSo) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::stall, false));
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 00b4");
  EXPECT_EQ(bench.unit.state().mode, DeviceMode::error);
}

struct ErrorRow {
  const char* request;
  const char* reply;
};

// D11: in ERROR every GET_*, DO_RESET and CANCEL_PROFILE are answered (status says ERROR); the
// rest gets SERVICE_FAILURE reason 3. TRANS_IDLE too (docs/decisions-local.md).
const ErrorRow kErrorRows[] = {
    {"GET_STATUS", "GET_STATUS reply 0000 00b4"},
    {"GET_IDENTIFICATION 0001", "GET_IDENTIFICATION reply 4c44 2d4f 454d 3130 3030"},
    {"GET_SIGNAL", "GET_SIGNAL reply 0000"},
    {"GET_CONFIG 0010", "GET_CONFIG reply 0010 0001 000a 0004"},
    {"GET_FUNCTION 0000", "GET_FUNCTION reply 0000 0003 0870"},
    {"CANCEL_PROFILE", "CANCEL_PROFILE reply 0000 00b4"},
    {"GET_PROFILE 0001 39ff", "SERVICE_FAILURE 0301 0003"},
    {"TRANS_IDLE", "SERVICE_FAILURE 0402 0003"},
    {"TRANS_ROTATE 0000", "SERVICE_FAILURE 0403 0003"},
    {"TRANS_MEASURE", "SERVICE_FAILURE 0404 0003"},
    {"SET_SIGNAL 0011", "SERVICE_FAILURE 0105 0003"},
    {"SET_CONFIG 0010 0001 000a 0004", "SERVICE_FAILURE 0201 0003"},
    {"SET_FUNCTION 0000 0003 0870 0000", "SERVICE_FAILURE 020a 0003"},
    {"SET_FILTER 0001 0000", "SERVICE_FAILURE 0209 0003"},
    {"SET_TIME_ABS 03e8", "SERVICE_FAILURE 0203 0003"},
};

class InError : public ::testing::TestWithParam<ErrorRow> {};

TEST_P(InError, AnswersAsD11Says) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::encoder, false));
  ASSERT_EQ(bench.unit.state().mode, DeviceMode::error);
  EXPECT_EQ(bench.reply_text(kTcp1, GetParam().request), GetParam().reply) << bench.unit.dump(bench.now);
  EXPECT_EQ(bench.unit.state().mode, DeviceMode::error);
}

INSTANTIATE_TEST_SUITE_P(D11, InError, ::testing::ValuesIn(kErrorRows));

TEST(MotorFaults, ResetLevelTwoLeavesErrorButAnUnrepairedMotorFailsAgain) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::stall, false));
  bench.advance_by(kRevolutionAt10Hz);
  ASSERT_EQ(bench.unit.state().mode, DeviceMode::error);
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  // Still stalled: the next spin fails at once.
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 00b4");
  // Repaired, reset: the head spins up as usual.
  bench.unit.clear_motor_fault();
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_ROTATE 0000"), "");
  bench.advance_by(bench.head.duration);
  EXPECT_EQ(bench.log.back().text(), "TRANS_ROTATE reply 0000 0002");
}

TEST(MotorFaults, FullResetFromErrorIsThePowerUpState) {
  Bench bench;
  stream(bench);
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::encoder, false));
  bench.unit.clear_motor_fault();
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0000"), "DO_RESET reply 0000");
  EXPECT_EQ(bench.unit.state(), power_up_state(bench.now, bench.unit.state().flash)) << bench.unit.dump(bench.now);
}

TEST(MotorFaults, LatentFaultInIdleShowsAtTheNextSpin) {
  Bench bench;
  bench.deliver(bench.unit.inject_motor_fault(bench.now, MotorFault::overspeed, false));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 0001");
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_ROTATE 0000"), "TRANS_ROTATE reply 0000 0094");
}

TEST(DeviceFaults, SpontaneousResetStopsTheStreamAndIsPowerUp) {
  Bench bench;
  stream(bench);
  const std::size_t profiles = bench.profiles_to(kCan1).size();
  bench.deliver(bench.unit.spontaneous_reset(bench.now));
  EXPECT_EQ(bench.unit.state(), power_up_state(bench.now, bench.unit.state().flash));
  bench.advance_by(1s);
  EXPECT_EQ(bench.profiles_to(kCan1).size(), profiles);
  EXPECT_EQ(bench.unit.diagnostics().spontaneous_resets, 1u);
}

TEST(DeviceFaults, PowerOnLosesRamKeepsFlash) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, "SET_FUNCTION 0000 0003 0960 0000"), "SET_FUNCTION reply 0000");
  (void)bench.unit.power_on(5s);
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_FUNCTION 0000"), "GET_FUNCTION reply 0000 0003 0870");
  EXPECT_EQ(bench.unit.diagnostics().power_cycles, 1u);
}

TEST(BeamFaults, InSectorWrapsThroughZero) {
  EXPECT_TRUE(in_sector(5700, 5600, 160));
  EXPECT_TRUE(in_sector(0, 5600, 160));
  EXPECT_TRUE(in_sector(159, 5600, 160));
  EXPECT_FALSE(in_sector(160, 5600, 160));
  EXPECT_FALSE(in_sector(3000, 5600, 160));
  EXPECT_TRUE(in_sector(100, 100, 200));
  EXPECT_FALSE(in_sector(200, 100, 200));
}

TEST(BeamFaults, BlindSectorGivesNoEchoOnlyInside) {
  Bench bench;
  BeamFaults faults;
  faults.blind.push_back(BlindFault{1600, 2000, 0.0});  // 100 .. 125 deg
  bench.unit.set_beam_faults(faults);
  stream(bench);
  const auto profiles = bench.profiles_to(kCan1);
  ASSERT_FALSE(profiles.empty());
  std::size_t blinded = 0, seen = 0;
  for (const auto& sector : profiles.back().sectors) {
    for (const auto& point : sector.points) {
      ++seen;
      const bool inside = point.direction_ticks >= 1600 && point.direction_ticks < 2000;
      if (inside) {
        EXPECT_EQ(point.distance_q8_m, 0) << point.direction_ticks;
        EXPECT_EQ(point.echo, 0) << point.direction_ticks;
        ++blinded;
      } else {
        EXPECT_NE(point.distance_q8_m, 0) << point.direction_ticks;
      }
    }
  }
  EXPECT_EQ(blinded, 100u);  // 25 deg at 0.25 deg
  EXPECT_GT(seen, blinded);
}

TEST(BeamFaults, BlindFractionIsDeterministicAndAboutTheFraction) {
  auto run = [](std::uint64_t seed) {
    Bench bench;
    bench.unit.set_beam_faults(BeamFaults{{BlindFault{std::nullopt, std::nullopt, 0.3}}, 0.0, seed});
    stream(bench);
    std::vector<std::uint16_t> distances;
    const auto profiles = bench.profiles_to(kCan1);
    for (const auto& sector : profiles.back().sectors) {
      for (const auto& point : sector.points) distances.push_back(point.distance_q8_m);
    }
    return distances;
  };
  const auto a = run(5);
  EXPECT_EQ(a, run(5));
  EXPECT_NE(a, run(6));
  const auto zeros = static_cast<double>(std::count(a.begin(), a.end(), 0));
  EXPECT_NEAR(zeros / static_cast<double>(a.size()), 0.3, 0.06);  // 1080 beams: sigma 0.014
}

// ECHO 2000 everywhere (twice the D6 threshold).
class BrightSource final : public MeasurementSource {
 public:
  void measure(const RevolutionQuery&, std::span<const BeamQuery> beams, std::span<BeamReturn> returns) override {
    for (std::size_t i = 0; i < beams.size(); ++i) returns[i] = BeamReturn{512, 2000};
  }
};

TEST(BeamFaults, WindowDirtScalesEchoAndDropsBelowThreshold) {
  for (const auto& [dirt, distance, echo] : {std::tuple{0.4, 512, 1200}, std::tuple{0.6, 0, 0}}) {
    FixedSpinUpHead head;
    BrightSource source;
    FakeTransportQuery transport;  // never busy
    ControlUnit unit({}, head, source);
    unit.set_beam_faults(BeamFaults{{}, dirt, 1});
    Actions spin = unit.handle_request(0s, kTcp1, telegram("TRANS_ROTATE 0000"), transport);
    (void)unit.on_timer(2s, spin.timers.at(0).id, transport);
    (void)unit.handle_request(2s, kTcp1, telegram("TRANS_MEASURE"), transport);
    Actions start = unit.handle_request(2s, kCan1, telegram("GET_PROFILE 0001 3fff"), transport);
    Actions profile = unit.on_timer(3s, start.timers.at(0).id, transport);
    ASSERT_EQ(profile.telegrams.size(), 1u);
    const auto decoded = protocol::decode_profile(profile.telegrams[0].payload);
    ASSERT_TRUE(decoded);
    const auto& point = decoded->sectors.at(0).points.at(0);
    EXPECT_EQ(point.distance_q8_m, distance) << dirt;
    EXPECT_EQ(point.echo, echo) << dirt;
  }
}

}  // namespace
}  // namespace ldoem::control::test
