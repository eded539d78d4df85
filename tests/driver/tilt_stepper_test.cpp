// TiltStepper: exact pulse sequences (D8) on a fake port with a fake sleeper, cross-checked by
// protocol's StepEdgeDetector, and the bytes a real pseudo terminal carries.
#include "ldoem/driver/tilt_stepper.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "pty_pair.hpp"

namespace ldoem::driver {
namespace {

namespace p = protocol;
using namespace std::chrono_literals;

class FakeSleeper final : public Sleeper {
 public:
  base::SimTime now() override { return now_; }
  void sleep_until(base::SimTime time) override {
    if (time > now_) {
      now_ = time;
    }
  }

 private:
  base::SimTime now_ = 1s;  // an arbitrary epoch: sequences are relative to the move's start
};

struct Write {
  base::SimTime at;
  std::uint8_t value;
  bool operator==(const Write&) const = default;
};

class FakeLptPort final : public LptPort {
 public:
  explicit FakeLptPort(Sleeper& clock) : clock_(clock) {}
  Status write_data(std::uint8_t value) override {
    if (fail_after_ && writes.size() >= *fail_after_) {
      return fail(make_error(ErrorKind::system, "write", name_, "scripted failure"));
    }
    writes.push_back(Write{clock_.now(), value});
    return ok();
  }
  const std::string& name() const override { return name_; }

  std::vector<Write> writes;
  std::optional<std::size_t> fail_after_;

 private:
  Sleeper& clock_;
  std::string name_ = "lpt:fake";
};

class TiltStepperTest : public ::testing::Test {
 protected:
  FakeSleeper sleeper_;
  FakeLptPort port_{sleeper_};
  TiltStepper stepper_{port_, sleeper_};
  const base::SimTime t0_ = 1s;
};

TEST_F(TiltStepperTest, ThreeFullStepsUp_GiveSetupThenRisingAndFallingEdges) {
  ASSERT_TRUE(stepper_.move(3, TiltDirection::increasing, StepMode::full_step, 100.0));
  const std::vector<Write> expected = {
      {t0_, 0x01},        {t0_ + 5ms, 0x03},  {t0_ + 10ms, 0x01}, {t0_ + 15ms, 0x03},
      {t0_ + 20ms, 0x01}, {t0_ + 25ms, 0x03}, {t0_ + 30ms, 0x01},
  };
  EXPECT_EQ(port_.writes, expected);
  EXPECT_EQ(stepper_.position_half_steps(), 6);
  EXPECT_NEAR(stepper_.tilt_angle_deg(), 0.27, 1e-12);
}

TEST_F(TiltStepperTest, HalfStepsDown_SetModeBitAndCountHalfSteps) {
  ASSERT_TRUE(stepper_.move(2, TiltDirection::decreasing, StepMode::half_step, 1000.0));
  const std::vector<Write> expected = {
      {t0_, 0x04}, {t0_ + 500us, 0x06}, {t0_ + 1ms, 0x04}, {t0_ + 1500us, 0x06}, {t0_ + 2ms, 0x04},
  };
  EXPECT_EQ(port_.writes, expected);
  EXPECT_EQ(stepper_.position_half_steps(), -2);
  EXPECT_NEAR(stepper_.tilt_angle_deg(), -0.09, 1e-12);
}

TEST_F(TiltStepperTest, SameDirectionAndMode_WritesNoSecondSetup) {
  ASSERT_TRUE(stepper_.move(1, TiltDirection::increasing, StepMode::full_step, 100.0));
  ASSERT_TRUE(stepper_.move(1, TiltDirection::increasing, StepMode::full_step, 100.0));
  ASSERT_EQ(port_.writes.size(), 5u);  // setup, (high, low) x 2
  EXPECT_EQ(port_.writes[3].value, 0x03);
}

TEST_F(TiltStepperTest, DirectionChange_SetsDirBeforeTheNextEdge) {
  ASSERT_TRUE(stepper_.move(2, TiltDirection::increasing, StepMode::full_step, 200.0));
  ASSERT_TRUE(stepper_.move(3, TiltDirection::decreasing, StepMode::half_step, 200.0));
  // The board's view (protocol's detector): every edge carries the direction and mode that
  // were commanded for it.
  p::StepEdgeDetector detector;
  std::vector<p::StepPulse> pulses;
  for (const Write& write : port_.writes) {
    if (auto pulse = detector.on_write(write.at, write.value)) {
      pulses.push_back(*pulse);
    }
  }
  ASSERT_EQ(pulses.size(), 5u);
  EXPECT_EQ(pulses[1].direction, TiltDirection::increasing);
  EXPECT_EQ(pulses[1].mode, StepMode::full_step);
  EXPECT_EQ(pulses[2].direction, TiltDirection::decreasing);
  EXPECT_EQ(pulses[2].mode, StepMode::half_step);
  double tilt_deg = 0.0;
  for (const auto& pulse : pulses) {
    tilt_deg += pulse.tilt_change_deg();
  }
  EXPECT_NEAR(tilt_deg, stepper_.tilt_angle_deg(), 1e-12);
  EXPECT_EQ(stepper_.position_half_steps(), 4 - 3);
}

TEST_F(TiltStepperTest, ZeroSteps_OnlySetsTheRegister) {
  ASSERT_TRUE(stepper_.move(0, TiltDirection::increasing, StepMode::half_step, 10.0));
  EXPECT_EQ(port_.writes, (std::vector<Write>{{t0_, 0x05}}));
  EXPECT_EQ(stepper_.position_half_steps(), 0);
}

TEST_F(TiltStepperTest, BadRate_IsInvalidArgumentAndWritesNothing) {
  // 1e-9 Hz and 1e-300 Hz: a step period the nanosecond clock cannot hold (was undefined behaviour).
  for (double rate : {0.0, -5.0, 1e-9, 1e-300, std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::quiet_NaN()}) {
    auto moved = stepper_.move(1, TiltDirection::increasing, StepMode::full_step, rate);
    ASSERT_FALSE(moved) << rate;
    EXPECT_EQ(moved.error().kind, ErrorKind::invalid_argument);
  }
  EXPECT_TRUE(port_.writes.empty());
}

TEST_F(TiltStepperTest, FailingWrite_StopsAndKeepsStepsAlreadyMade) {
  port_.fail_after_ = 4;  // setup, high, low, high succeed; the next low fails
  auto moved = stepper_.move(5, TiltDirection::increasing, StepMode::full_step, 100.0);
  ASSERT_FALSE(moved);
  EXPECT_EQ(moved.error().operation, "write");
  EXPECT_EQ(stepper_.position_half_steps(), 4);  // two rising edges were written
}

TEST(TiltStepperCancel, InterruptedSleeper_EndsALongMoveWithClockLow) {
  MonotonicSleeper sleeper;
  FakeLptPort port(sleeper);
  TiltStepper stepper(port, sleeper);
  std::thread canceller([&] {
    std::this_thread::sleep_for(50ms);
    sleeper.interrupt();
  });
  const auto start = std::chrono::steady_clock::now();
  auto moved = stepper.move(1000, TiltDirection::increasing, StepMode::full_step, 1.0);  // 1000 s
  canceller.join();
  EXPECT_LT(std::chrono::steady_clock::now() - start, 2s);
  ASSERT_FALSE(moved);
  EXPECT_EQ(moved.error().kind, ErrorKind::interrupted);
  ASSERT_FALSE(port.writes.empty());
  EXPECT_EQ(port.writes.back().value & p::kLptClockBit, 0) << "CLK must be left low";
  // Later moves fail at once too: the hub is shutting down.
  auto again = stepper.move(1, TiltDirection::increasing, StepMode::full_step, 1.0);
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error().kind, ErrorKind::interrupted);
}

TEST_F(TiltStepperTest, MoveToAngle_PicksTheNearestStepCount) {
  ASSERT_TRUE(stepper_.move_to_angle(0.9, StepMode::full_step, 1000.0));
  EXPECT_EQ(stepper_.position_half_steps(), 20);  // 10 full steps of 0.09 deg
  ASSERT_TRUE(stepper_.move_to_angle(0.85, StepMode::half_step, 1000.0));
  EXPECT_EQ(stepper_.position_half_steps(), 19);  // one half step down: 0.855 deg
  EXPECT_NEAR(stepper_.tilt_angle_deg(), 0.855, 1e-12);
}

TEST(PtyLptPort, StepperBytes_ArriveOnThePtyInOrder) {
  test::PtyPair pty;
  auto port = PtyLptPort::open(pty.slave_path());
  ASSERT_TRUE(port) << describe(port.error());
  MonotonicSleeper sleeper;
  TiltStepper stepper(**port, sleeper);
  ASSERT_TRUE(stepper.move(2, TiltDirection::increasing, StepMode::full_step, 20000.0));
  ASSERT_TRUE(stepper.move(1, TiltDirection::decreasing, StepMode::half_step, 20000.0));
  const protocol::Bytes expected{0x01, 0x03, 0x01, 0x03, 0x01, 0x04, 0x06, 0x04};
  EXPECT_EQ(pty.read_master(expected.size()), expected);
}

TEST(OpenLptPort, PtyEndpoint_OpensAPtyPort) {
  test::PtyPair pty;
  auto port = open_lpt_port(LptEndpoint{LptBackend::pty, pty.slave_path()});
  ASSERT_TRUE(port) << describe(port.error());
  EXPECT_EQ((*port)->name(), "lpt:pty:" + pty.slave_path());
  ASSERT_TRUE((*port)->write_data(0x07));
  EXPECT_EQ(pty.read_master(1), protocol::Bytes{0x07});
}

TEST(OpenLptPort, MissingDevices_GiveErrorsNamingThem) {
  auto ppdev = open_lpt_port(LptEndpoint{LptBackend::ppdev, "/nonexistent/parport9"});
  ASSERT_FALSE(ppdev);
  EXPECT_EQ(ppdev.error().object, "lpt:/nonexistent/parport9");
  auto gpio = open_lpt_port(LptEndpoint{LptBackend::gpio, "no-such-chip-ldoem"});
  ASSERT_FALSE(gpio);
  EXPECT_EQ(gpio.error().object, "lpt:gpio:no-such-chip-ldoem");
  auto tcp = open_lpt_port(TcpEndpoint{"127.0.0.1"});
  ASSERT_FALSE(tcp);
  EXPECT_EQ(tcp.error().kind, ErrorKind::invalid_argument);
}

}  // namespace
}  // namespace ldoem::driver
