// The FaultInjector: scheduler decisions become control-unit effects and event lines.
#include "ldoem/fault_injection/fault_injector.hpp"

#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::fault_injection {
namespace {

using control::test::Bench;
using control::test::kTcp1;
using namespace std::chrono_literals;

faults::FaultSpec spec(faults::FaultKind kind, faults::Trigger trigger = faults::TriggerNow{}) {
  faults::FaultSpec entry;
  entry.kind = kind;
  entry.trigger = trigger;
  return entry;
}

std::vector<std::string> names(const std::vector<InjectorEvent>& events) {
  std::vector<std::string> result;
  for (const auto& event : events) result.push_back(event.name);
  return result;
}

TEST(FaultInjector, SceneStallAtTimeStopsTheHeadAndClearsAfterItsDuration) {
  Bench bench;
  auto stall = spec(faults::FaultKind::motor_stall, faults::TriggerAt{3s});
  stall.duration = 1s;
  FaultInjector injector({stall}, 1, false, bench.unit);
  bench.enter_measure();
  std::vector<InjectorEvent> ignored;
  injector.note_state(bench.now, ignored);  // the daemon does this after every event
  EXPECT_EQ(injector.next_deadline(), faults::SimTime(3s));
  bench.advance_to(3s);
  auto out = injector.advance(3s);
  bench.deliver(std::move(out.actions));
  EXPECT_EQ(names(out.events), (std::vector<std::string>{"FAULT_INJECTED"}));
  EXPECT_EQ(bench.reply_text(kTcp1, "GET_STATUS"), "GET_STATUS reply 0000 00b3");
  bench.advance_to(3100ms);
  std::vector<InjectorEvent> state;
  injector.note_state(bench.now, state);
  ASSERT_EQ(names(state), (std::vector<std::string>{"STATE_CHANGED"}));
  EXPECT_EQ(state[0].data["to"], "ERROR");
  EXPECT_EQ(state[0].data["status_byte"], 0xB4);
  out = injector.advance(4s);
  EXPECT_EQ(names(out.events), (std::vector<std::string>{"FAULT_CLEARED"}));
  EXPECT_FALSE(bench.unit.hardware_motor_fault());
  // Cleared: DO_RESET 2 brings IDLE and the head spins again.
  EXPECT_EQ(bench.reply_text(kTcp1, "DO_RESET 0002"), "DO_RESET reply 0002");
  EXPECT_EQ(bench.reply_text(kTcp1, "TRANS_ROTATE 0000"), "");
}

// L-faults-5: off (dark), then power back (booting: the old connections are reset, the device
// in its D4 power-up state), then serving after the boot time.
TEST(FaultInjector, PowerCycleGoesDarkThenBootsThenServes) {
  Bench bench;
  FaultInjector injector({}, 1, false, bench.unit, 3s);
  bench.enter_measure();
  std::vector<InjectorEvent> ignored;
  injector.note_state(bench.now, ignored);
  auto cycle = spec(faults::FaultKind::power_cycle);
  cycle.off = 2s;
  faults::FaultId id = 0;
  auto out = injector.inject(bench.now, cycle, id);
  EXPECT_EQ(out.power_steps, std::vector<Power>{Power::off});
  EXPECT_EQ(injector.power(), Power::off);
  EXPECT_EQ(names(out.events), (std::vector<std::string>{"FAULT_INJECTED", "POWER_OFF", "FAULT_CLEARED"}));
  const faults::SimTime off_at = bench.now;
  EXPECT_EQ(injector.next_deadline(), off_at + 2s);
  out = injector.advance(off_at + 2s);
  EXPECT_EQ(out.power_steps, std::vector<Power>{Power::booting});
  EXPECT_EQ(injector.power(), Power::booting);
  EXPECT_EQ(names(out.events), (std::vector<std::string>{"POWER_ON", "STATE_CHANGED"}));
  EXPECT_EQ(out.events[0].data["boot_s"], 3.0);
  EXPECT_EQ(bench.unit.state(), control::power_up_state(off_at + 2s, bench.unit.state().flash));
  EXPECT_EQ(injector.next_deadline(), off_at + 5s);
  out = injector.advance(off_at + 5s);
  EXPECT_EQ(out.power_steps, std::vector<Power>{Power::on});
  EXPECT_EQ(injector.power(), Power::on);
  EXPECT_EQ(names(out.events), (std::vector<std::string>{"BOOTED"}));
  EXPECT_EQ(out.events[0].at, off_at + 5s);
}

// A clock that jumps over the whole boot (or a boot time of 0) gives every step, in order.
TEST(FaultInjector, PowerCycleStepsInOrderWhenTimeJumpsOverTheBoot) {
  Bench bench;
  FaultInjector injector({}, 1, false, bench.unit, 0s);
  auto cycle = spec(faults::FaultKind::power_cycle);
  cycle.off = 1s;
  faults::FaultId id = 0;
  (void)injector.inject(bench.now, cycle, id);
  const auto out = injector.advance(bench.now + 10s);
  EXPECT_EQ(out.power_steps, (std::vector<Power>{Power::booting, Power::on}));
  EXPECT_EQ(names(out.events), (std::vector<std::string>{"POWER_ON", "BOOTED"}));
}

TEST(FaultInjector, BlindAndDirtReachTheBeams) {
  Bench bench;
  FaultInjector injector({}, 1, false, bench.unit);
  auto dirt = spec(faults::FaultKind::window_dirt);
  dirt.fraction = 0.9;  // the bench's ECHO values are tiny: every return drops
  faults::FaultId id = 0;
  (void)injector.inject(0s, dirt, id);
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(300ms);
  const auto profiles = bench.profiles_to(kTcp1);
  ASSERT_EQ(profiles.size(), 1u);
  for (const auto& point : profiles[0].sectors[0].points) EXPECT_EQ(point.distance_q8_m, 0);
  bool found = false;
  (void)injector.clear(bench.now, id, found);
  EXPECT_TRUE(found);
  bench.request(kTcp1, "GET_PROFILE 0001 39ff");
  bench.advance_by(300ms);
  const auto after = bench.profiles_to(kTcp1);
  ASSERT_EQ(after.size(), 2u);
  EXPECT_NE(after[1].sectors[0].points[0].distance_q8_m, 0);
}

// Same faults, seed and conversation: the same event log, twice.
TEST(FaultInjector, EventLogIsDeterministic) {
  auto run = [](std::uint64_t seed) {
    Bench bench;
    auto flaky = spec(faults::FaultKind::drop_reply, faults::TriggerProbability{0.3});
    auto stall = spec(faults::FaultKind::motor_stall, faults::TriggerAt{4s});
    FaultInjector injector({flaky, stall}, seed, false, bench.unit);
    std::string log;
    auto record = [&log](const std::vector<InjectorEvent>& events) {
      for (const auto& event : events) log += event.name + " " + event.data.dump() + " " + std::to_string(event.at.count()) + "\n";
    };
    for (int i = 0; i < 60; ++i) {
      bench.advance_by(100ms);
      auto out = injector.advance(bench.now);
      bench.deliver(std::move(out.actions));
      record(out.events);
      out = injector.on_request(bench.now, 0x0102, protocol::Transport::tcp);
      record(out.events);
      std::vector<faults::FaultEvent> used;
      if (injector.scheduler().take_any_wire_fault(bench.now, protocol::Transport::tcp, 0x0102, used)) log += "dropped\n";
      InjectorOutput wire;
      injector.events_from(used, wire);
      record(wire.events);
      bench.request(kTcp1, "GET_STATUS");
    }
    return log;
  };
  const std::string first = run(11);
  EXPECT_EQ(first, run(11));
  EXPECT_NE(first, run(12));
  EXPECT_NE(first.find("motor_stall"), std::string::npos);
  EXPECT_NE(first.find("dropped"), std::string::npos);
}

}  // namespace
}  // namespace ldoem::fault_injection
