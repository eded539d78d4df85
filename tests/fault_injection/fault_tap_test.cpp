// The FaultTap on a fake device and a fake clock: the telegram-level wire faults and the power-off
// silence, without a daemon (the tap acts only through FaultedDevice and endpoints::Scheduler).
#include "ldoem/fault_injection/fault_tap.hpp"

#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "control_test_support.hpp"

namespace ldoem::fault_injection {
namespace {

using control::test::Bench;
using control::test::kTcp1;
using endpoints::WireVerdict;
using namespace std::chrono_literals;

// Records what the tap does to the device.
struct TapFakeDevice final : FaultedDevice {
  explicit TapFakeDevice(control::ControlUnit& unit_in) : unit(unit_in) {}
  control::ControlUnit& control_unit() override { return unit; }
  void perform_actions(base::SimTime, const control::Actions&) override { ++actions_performed; }
  void set_power(endpoints::DevicePower power) override { powers.push_back(power); }
  void send_to_host(protocol::ConnectionId, protocol::ByteView payload, bool) override {
    sent.emplace_back(payload.begin(), payload.end());
  }
  void disconnect(protocol::ConnectionId) override { ++disconnects; }
  void set_wire_tap(endpoints::WireTap* tap_in) override { tap = tap_in; }
  endpoints::WireTap* wire_tap() const override { return tap; }
  void set_fault_hook(endpoints::WireFaultHook* hook_in) override { hook = hook_in; }

  control::ControlUnit& unit;
  endpoints::WireTap* tap = nullptr;
  endpoints::WireFaultHook* hook = nullptr;
  std::vector<protocol::Bytes> sent;
  std::vector<endpoints::DevicePower> powers;
  int actions_performed = 0;
  int disconnects = 0;
};

// Deadlines fire only when the test advances the clock.
struct TapFakeClock final : endpoints::Scheduler {
  base::SimTime now() override { return at; }
  base::SimTime at_wall_time(endpoints::WallTime) override { return at; }
  Key add(base::SimTime when, Action action) override {
    const Key key{when, next++};
    queued.emplace(key, std::move(action));
    return key;
  }
  void cancel(const Key& key) override { queued.erase(key); }
  void advance_to(base::SimTime to) {
    while (!queued.empty() && queued.begin()->first.first <= to) {
      auto due = queued.extract(queued.begin());
      at = due.key().first;
      due.mapped()(at);
    }
    at = to;
  }
  base::SimTime at{};
  std::uint64_t next = 0;
  std::map<Key, Action> queued;
};

endpoints::WireTelegram reply(base::SimTime at) {
  // A GET_STATUS reply (0x8204: the request 0x0204 with the response bit).
  return {protocol::WireDirection::device_to_host, kTcp1, at, protocol::Bytes{0x82, 0x04, 0x00, 0x00}, false};
}

faults::FaultSpec wire_fault(faults::FaultKind kind) {
  faults::FaultSpec entry;
  entry.kind = kind;
  entry.trigger = faults::TriggerNow{};
  entry.count = 1;
  return entry;
}

struct TapBench {
  Bench bench;
  TapFakeDevice device{bench.unit};
  TapFakeClock clock;
  std::ostringstream log_text;
  endpoints::Logger logger{log_text, endpoints::LogLevel::warn};
  std::vector<std::string> events;
  FaultTap tap{device, clock, logger, {}, [this](const InjectorEvent& event) { events.push_back(event.name); }};
};

TEST(FaultTap, PlugsIntoTheDeviceAndUnplugsAtTheEnd) {
  Bench bench;
  TapFakeDevice device{bench.unit};
  TapFakeClock clock;
  std::ostringstream log_text;
  const endpoints::Logger logger{log_text, endpoints::LogLevel::warn};
  {
    FaultTap tap(device, clock, logger, {}, [](const InjectorEvent&) {});
    EXPECT_EQ(device.tap, &tap);
    EXPECT_NE(device.hook, nullptr);
  }
  EXPECT_EQ(device.tap, nullptr);
  EXPECT_EQ(device.hook, nullptr);
}

TEST(FaultTap, DropReplyLosesOneReplyThenPasses) {
  TapBench b;
  EXPECT_NE(b.tap.inject(wire_fault(faults::FaultKind::drop_reply)), 0u);
  auto first = reply(0s);
  EXPECT_EQ(b.tap.on_telegram(first), WireVerdict::drop);
  auto second = reply(0s);
  EXPECT_EQ(b.tap.on_telegram(second), WireVerdict::pass);
  EXPECT_EQ(b.tap.injections(), 1u);
}

TEST(FaultTap, TruncateReplyKeepsTheFirstBytes) {
  TapBench b;
  auto truncate = wire_fault(faults::FaultKind::truncate_reply);
  truncate.bytes_kept = 2;
  b.tap.inject(truncate);
  auto telegram = reply(0s);
  EXPECT_EQ(b.tap.on_telegram(telegram), WireVerdict::pass);
  EXPECT_EQ(telegram.payload, (protocol::Bytes{0x82, 0x04}));
}

TEST(FaultTap, DelayReplyHoldsTheReplyUntilItsTime) {
  TapBench b;
  auto delay = wire_fault(faults::FaultKind::delay_reply);
  delay.delay = 500ms;
  b.tap.inject(delay);
  auto telegram = reply(0s);
  EXPECT_EQ(b.tap.on_telegram(telegram), WireVerdict::drop);
  b.clock.advance_to(499ms);
  EXPECT_TRUE(b.device.sent.empty());
  b.clock.advance_to(500ms);
  ASSERT_EQ(b.device.sent.size(), 1u);
  EXPECT_EQ(b.device.sent[0], (protocol::Bytes{0x82, 0x04, 0x00, 0x00}));
}

TEST(FaultTap, AClosedConnectionTakesItsDelayedRepliesWithIt) {
  TapBench b;
  auto delay = wire_fault(faults::FaultKind::delay_reply);
  delay.delay = 500ms;
  b.tap.inject(delay);
  auto telegram = reply(0s);
  EXPECT_EQ(b.tap.on_telegram(telegram), WireVerdict::drop);
  b.tap.forget_delayed(kTcp1);
  b.clock.advance_to(1s);
  EXPECT_TRUE(b.device.sent.empty());
}

TEST(FaultTap, PoweredOffTheDeviceHearsAndSaysNothing) {
  TapBench b;
  auto cycle = wire_fault(faults::FaultKind::power_cycle);
  cycle.count.reset();
  cycle.off = 1s;
  b.tap.inject(cycle);
  EXPECT_EQ(b.tap.power(), Power::off);
  ASSERT_FALSE(b.device.powers.empty());
  EXPECT_EQ(b.device.powers.front(), endpoints::DevicePower::off);
  auto out = reply(0s);
  EXPECT_EQ(b.tap.on_telegram(out), WireVerdict::drop);
  endpoints::WireTelegram in{protocol::WireDirection::host_to_device, kTcp1, 0s, protocol::Bytes{0x02, 0x04}, false};
  EXPECT_EQ(b.tap.on_telegram(in), WireVerdict::drop);
  b.clock.advance_to(2s);  // off 1 s, then a boot of 0 s: on again
  EXPECT_EQ(b.tap.power(), Power::on);
  EXPECT_EQ(b.tap.on_telegram(in), WireVerdict::pass);
}

}  // namespace
}  // namespace ldoem::fault_injection
