// D11 lpt_lose_steps and lpt_jam on the gpio LPT back end (D8): the test pulls DIR/CLK of the
// gpio-sim chip one edge at a time, and the plate's step count (query-status tilt_steps) says
// which pulses it followed. Inside the gpio-sim UML kernel only (label gpio; FAILS without it):
//   scripts/uml/run.sh --kernel "$(scripts/uml/build-gpio-kernel.sh)" --gpio -- ctest --test-dir BUILD -L gpio -R wire_faults
#include <gtest/gtest.h>

#include <thread>

#include "ldoem/test_support/gpio_sim_chip.hpp"
#include "wire_fault_support.hpp"

namespace ldoem::wire_faults::test {
namespace {

using namespace std::chrono_literals;
using daemon::test::minimal_scene_text;

constexpr int kDirLine = 0;
constexpr int kClkLine = 1;
constexpr auto kEdgeGap = 10ms;  // one edge at a time (tests/daemon/daemon_gpio_test.cpp says why)

struct GpioLptDaemon {
  test_support::SimChip chip;
  std::string why_not;
  TempDir dir;
  std::string control = dir.path("ctl.sock");
  std::optional<FaultyDaemon> daemon;

  explicit GpioLptDaemon(const std::string& faults) {
    auto found = test_support::sim_chip(why_not);
    if (!found) return;
    chip = *found;
    for (const int line : {0, 1, 2}) test_support::pull_sim_line(chip, line, false);
    std::this_thread::sleep_for(kEdgeGap);
    daemon.emplace(minimal_scene_text() + "faults:\n" + faults,
                   std::vector<std::string>{"--lpt", "lpt:gpio:" + chip.label, "--control", control});
  }
  bool ready() { return daemon && daemon->ready(); }
  void steps_up(int count) {
    ASSERT_TRUE(test_support::pull_sim_line(chip, kDirLine, true));
    std::this_thread::sleep_for(kEdgeGap);
    for (int i = 0; i < count; ++i) {
      ASSERT_TRUE(test_support::pull_sim_line(chip, kClkLine, true));
      std::this_thread::sleep_for(kEdgeGap);
      ASSERT_TRUE(test_support::pull_sim_line(chip, kClkLine, false));
      std::this_thread::sleep_for(kEdgeGap);
    }
  }
  std::optional<std::uint64_t> tilt_steps_after_settling() {
    std::this_thread::sleep_for(200ms);
    const auto status = control_request(control, {{"execute", "query-status"}});
    if (!status || !status->contains("return")) return std::nullopt;
    return (*status)["return"]["tilt_steps"].get<std::uint64_t>();
  }
};

TEST(WireFaultsGpio, LoseSteps_ThePlateMissesExactlyCountPulses) {
  GpioLptDaemon d("  - {kind: lpt_lose_steps, count: 2}\n");
  ASSERT_TRUE(d.ready()) << d.why_not << (d.daemon ? d.daemon->diagnostics() : "");
  d.steps_up(6);
  EXPECT_EQ(d.tilt_steps_after_settling(), std::optional<std::uint64_t>(4));
  d.steps_up(3);
  EXPECT_EQ(d.tilt_steps_after_settling(), std::optional<std::uint64_t>(7));
}

TEST(WireFaultsGpio, Jam_ThePlateFollowsNothingUntilCleared) {
  GpioLptDaemon d("  - {kind: lpt_jam}\n");
  ASSERT_TRUE(d.ready()) << d.why_not << (d.daemon ? d.daemon->diagnostics() : "");
  d.steps_up(5);
  EXPECT_EQ(d.tilt_steps_after_settling(), std::optional<std::uint64_t>(0));
  const auto cleared = control_request(d.control, {{"execute", "clear-fault"}});
  ASSERT_TRUE(cleared && cleared->contains("return"));
  d.steps_up(3);
  EXPECT_EQ(d.tilt_steps_after_settling(), std::optional<std::uint64_t>(3));
}

}  // namespace
}  // namespace ldoem::wire_faults::test
