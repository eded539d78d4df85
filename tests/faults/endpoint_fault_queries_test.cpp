// What the endpoints' fault hook reads from the scheduler (D11): garbage bytes as a pure
// function of seed and fault id, connection-level faults found whatever service they name, and
// the faults that last until cleared when given neither duration nor count.
#include <gtest/gtest.h>

#include <algorithm>

#include "ldoem/faults/fault_scheduler.hpp"
#include "request_codes.hpp"

namespace ldoem::faults {
namespace {

using namespace std::chrono_literals;
using test::kGetStatus;

TEST(FaultGarbage, IsAPureFunctionOfSeedAndIdWithoutAFrameStart) {
  const auto bytes = fault_garbage(7, 1, 4096);
  EXPECT_EQ(bytes, fault_garbage(7, 1, 4096));
  EXPECT_NE(bytes, fault_garbage(8, 1, 4096));
  EXPECT_NE(bytes, fault_garbage(7, 2, 4096));
  EXPECT_EQ(std::count(bytes.begin(), bytes.end(), std::uint8_t{0x02}), 0);
  // A prefix is the start of a longer run: the n-th byte depends on n only.
  const auto short_run = fault_garbage(7, 1, 9);
  EXPECT_TRUE(std::equal(short_run.begin(), short_run.end(), bytes.begin()));
  EXPECT_EQ(short_run, (std::vector<std::uint8_t>{0x48, 0xBD, 0x68, 0x1C, 0xEE, 0x96, 0x7F, 0xD7, 0x20}));
  // Every other value occurs: the bytes are not a short pattern.
  for (int value = 0; value < 256; ++value) {
    if (value == 0x02) continue;
    EXPECT_NE(std::count(bytes.begin(), bytes.end(), static_cast<std::uint8_t>(value)), 0) << value;
  }
}

TEST(FindActiveOn, IgnoresTheServiceButNotTheTransportOrTheEnd) {
  FaultSpec stall;
  stall.kind = FaultKind::tcp_stall;
  stall.trigger = TriggerOnNth{kGetStatus, 1};
  stall.duration = 2s;
  FaultScheduler scheduler({stall}, 1);
  std::vector<FaultEvent> events;
  EXPECT_EQ(scheduler.find_active_on(0s, FaultKind::tcp_stall, Transport::tcp), nullptr);
  scheduler.on_request(1s, kGetStatus, Transport::tcp, events);
  const ActiveFault* found = scheduler.find_active_on(1s, FaultKind::tcp_stall, Transport::tcp);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->spec.service, std::optional<std::uint16_t>(kGetStatus));  // the trigger's, not a filter here
  EXPECT_EQ(found->until, std::optional<SimTime>(3s));
  EXPECT_EQ(scheduler.find_active_on(2999ms, FaultKind::tcp_stall, Transport::serial), nullptr);
  EXPECT_EQ(scheduler.find_active_on(3s, FaultKind::tcp_stall, Transport::tcp), nullptr);  // over, not yet cleared
}

TEST(FindActiveOn, ConnectionFaultsWithoutDurationOrCountLastUntilCleared) {
  for (const FaultKind kind : {FaultKind::tcp_stall, FaultKind::bandwidth, FaultKind::isotp_fc_wait, FaultKind::lpt_jam}) {
    FaultScheduler scheduler;
    std::vector<FaultEvent> events;
    FaultSpec spec;
    spec.kind = kind;
    const FaultId id = scheduler.inject(0s, spec, events);
    const Transport transport = applies_to(kind, Transport::tcp) ? Transport::tcp
                                : applies_to(kind, Transport::can) ? Transport::can
                                                                    : Transport::lpt;
    ASSERT_NE(scheduler.find_active_on(1000s, kind, transport), nullptr) << fault_name(kind);
    EXPECT_FALSE(scheduler.active().front().remaining) << fault_name(kind);
    EXPECT_TRUE(scheduler.clear(1000s, id, events));
    EXPECT_EQ(scheduler.find_active_on(1000s, kind, transport), nullptr);
  }
}

TEST(TakeWireFault, WithoutAServiceMatchesAFaultThatNamesOne) {
  FaultSpec lose;
  lose.kind = FaultKind::lpt_lose_steps;
  lose.trigger = TriggerOnNth{kGetStatus, 1};
  lose.count = 2;
  FaultScheduler scheduler({lose}, 1);
  std::vector<FaultEvent> events;
  scheduler.on_request(0s, kGetStatus, Transport::tcp, events);
  EXPECT_TRUE(scheduler.take_wire_fault(0s, FaultKind::lpt_lose_steps, Transport::lpt, std::nullopt, events));
  EXPECT_TRUE(scheduler.take_wire_fault(0s, FaultKind::lpt_lose_steps, Transport::lpt, std::nullopt, events));
  EXPECT_FALSE(scheduler.take_wire_fault(0s, FaultKind::lpt_lose_steps, Transport::lpt, std::nullopt, events));
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().reason, "count used");
}

}  // namespace
}  // namespace ldoem::faults
