// ldoem-emud's gpio LPT back end (D8) for real: the daemon reads DIR/CLK/MODE of the gpio-sim
// chip `ldoem-lpt`, and this test plays the drive board's host by pulling the simulated lines
// one edge at a time through gpio-sim's sysfs `pull` attributes. Runs inside the gpio-sim UML
// kernel only:
//   scripts/uml/run.sh --kernel "$(scripts/uml/build-gpio-kernel.sh)" --gpio -- ctest --test-dir BUILD -L gpio
// Without gpio-sim it FAILS (never skips).
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <numbers>
#include <thread>

#include "daemon_process.hpp"
#include "host_link.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/test_support/gpio_sim_chip.hpp"

namespace ldoem::daemon::test {
namespace {

using namespace std::chrono_literals;
using test_support::pull_sim_line;
using test_support::sim_chip;
using test_support::SimChip;

constexpr int kDirLine = 0;  // D8: DATA0
constexpr int kClkLine = 1;  // D8: DATA1
constexpr int kModeLine = 2; // D8: DATA2
// One edge at a time: the v1 uAPI reads an edge's direction from the line's level in the IRQ
// thread, so two edges on one line closer than that thread runs could be reported as one
// (docs/uml-harness.md). 10 ms is far above that in the UML guest.
constexpr auto kEdgeGap = 10ms;

class DaemonGpio : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why_not;
    auto chip = sim_chip(why_not);
    ASSERT_TRUE(chip.has_value()) << why_not;
    chip_ = *chip;
    for (const int line : {kDirLine, kClkLine, kModeLine}) ASSERT_TRUE(pull(line, false));
    std::this_thread::sleep_for(kEdgeGap);
    const std::string scene = dir_.write("scene.yaml", minimal_scene_text());
    auto started = DaemonProcess::start({"--scene", scene, "--lpt", "lpt:gpio:" + chip_.label, "--no-can", "--tcp",
                                     "tcp:127.0.0.1:0", "--no-flash", "--virtual-time", "--timeout", "120"});
    if (started) process_.emplace(std::move(*started));
    ASSERT_TRUE(process_ && process_->wait_ready()) << (process_ ? process_->stderr_text() : "did not start");
    ASSERT_TRUE(process_->endpoints().contains("lpt")) << process_->stdout_text();
    host_ = TcpHost::connect(process_->tcp_port());
    ASSERT_TRUE(host_);
  }

  bool pull(int line, bool up) {
    const bool pulled = pull_sim_line(chip_, line, up);
    EXPECT_TRUE(pulled) << "pulling line " << line << " of " << chip_.sysfs;
    return pulled;
  }

  // D8: direction first, then `count` clock pulses, each edge on its own.
  void step(bool up, int count) {
    ASSERT_TRUE(pull(kDirLine, up));
    std::this_thread::sleep_for(kEdgeGap);
    for (int i = 0; i < count; ++i) {
      ASSERT_TRUE(pull(kClkLine, true));
      std::this_thread::sleep_for(kEdgeGap);
      ASSERT_TRUE(pull(kClkLine, false));
      std::this_thread::sleep_for(kEdgeGap);
    }
  }

  std::optional<Bytes> reply_to(std::string_view request) {
    host_->send(telegram(request));
    return host_->next_payload();
  }

  std::optional<std::uint16_t> distance_ahead() {
    host_->send(telegram("GET_PROFILE 0001 39ff"));
    const auto payload = host_->next_payload();
    if (!payload) return std::nullopt;
    const auto profile = protocol::decode_profile(*payload);
    EXPECT_TRUE(profile) << to_hex(*payload);
    return profile ? distance_at_angle_zero(*profile) : std::nullopt;
  }

  // lpt_steps of the daemon's SIGUSR1 counter line; nothing when no line came.
  std::optional<std::uint64_t> lpt_steps() {
    process_->signal(SIGUSR1);
    std::this_thread::sleep_for(300ms);
    const std::string text = process_->stderr_text();
    const auto field = text.rfind("lpt_steps=");
    if (field == std::string::npos) return std::nullopt;
    return std::stoull(text.substr(field + 10));
  }

  SimChip chip_;
  TempDir dir_;
  std::optional<DaemonProcess> process_;
  std::optional<TcpHost> host_;
};

std::uint16_t q8_of_wall_at_tilt(double tilt_deg) {
  return static_cast<std::uint16_t>(std::lround(256.0 * 5.0 / std::cos(tilt_deg * std::numbers::pi / 180.0)));
}

TEST_F(DaemonGpio, ClockEdgesWithDirectionUp_AreCountedAndTiltTheBeam) {
  reply_to("TRANS_ROTATE 0000");
  reply_to("TRANS_MEASURE");
  EXPECT_EQ(distance_ahead(), std::optional<std::uint16_t>(1280));  // level: the wall 5 m ahead
  step(true, 100);  // D8: 100 full steps of 0.09 deg = 9 deg up
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(lpt_steps(), std::optional<std::uint64_t>(100)) << process_->stderr_text();
  EXPECT_EQ(distance_ahead(), std::optional<std::uint16_t>(q8_of_wall_at_tilt(9.0)));
}

TEST_F(DaemonGpio, DirectionDownAndHalfStepMode_StepBackByHalfSteps) {
  reply_to("TRANS_ROTATE 0000");
  reply_to("TRANS_MEASURE");
  step(true, 100);   // 9 deg up
  ASSERT_TRUE(pull(kModeLine, true));  // D8: half steps of 0.045 deg
  std::this_thread::sleep_for(kEdgeGap);
  step(false, 40);   // 1.8 deg down: 7.2 deg
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(lpt_steps(), std::optional<std::uint64_t>(140)) << process_->stderr_text();
  EXPECT_EQ(distance_ahead(), std::optional<std::uint16_t>(q8_of_wall_at_tilt(7.2)));
}

TEST_F(DaemonGpio, EdgesOnDirAndModeAlone_AreNoSteps) {
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(pull(kDirLine, true));
    std::this_thread::sleep_for(kEdgeGap);
    ASSERT_TRUE(pull(kModeLine, true));
    std::this_thread::sleep_for(kEdgeGap);
    ASSERT_TRUE(pull(kDirLine, false));
    std::this_thread::sleep_for(kEdgeGap);
    ASSERT_TRUE(pull(kModeLine, false));
    std::this_thread::sleep_for(kEdgeGap);
  }
  EXPECT_EQ(lpt_steps(), std::optional<std::uint64_t>(0)) << process_->stderr_text();
  EXPECT_EQ(reply_to("GET_STATUS"), std::optional<Bytes>(telegram("GET_STATUS reply 0000 0001")));
}

}  // namespace
}  // namespace ldoem::daemon::test
