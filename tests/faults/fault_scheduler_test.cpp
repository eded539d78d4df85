// The D11 scheduler: triggers, durations, counts, wire-fault matching, determinism.
#include "ldoem/faults/fault_scheduler.hpp"

#include <gtest/gtest.h>

#include "request_codes.hpp"

namespace ldoem::faults {
namespace {

using namespace std::chrono_literals;
using test::kGetProfile;
using test::kGetStatus;

FaultSpec spec_of(FaultKind kind, Trigger trigger = TriggerNow{}) {
  FaultSpec spec;
  spec.kind = kind;
  spec.trigger = trigger;
  return spec;
}

TEST(FaultScheduler, NoFaultsIsIdle) {
  FaultScheduler scheduler({}, 1);
  EXPECT_TRUE(scheduler.idle());
  std::vector<FaultEvent> events;
  scheduler.advance(10s, events);
  scheduler.on_request(10s, kGetStatus, Transport::tcp, events);
  EXPECT_TRUE(events.empty());
  EXPECT_FALSE(scheduler.next_deadline());
}

TEST(FaultScheduler, AtTimeStartsAndDurationEnds) {
  FaultSpec stall = spec_of(FaultKind::motor_stall, TriggerAt{2s});
  stall.duration = 1500ms;
  FaultScheduler scheduler({stall}, 1);
  std::vector<FaultEvent> events;
  EXPECT_EQ(scheduler.next_deadline(), SimTime(2s));
  scheduler.advance(1999ms, events);
  EXPECT_TRUE(events.empty());
  scheduler.advance(2s, events);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].what, FaultEventKind::injected);
  EXPECT_EQ(events[0].kind, FaultKind::motor_stall);
  EXPECT_TRUE(scheduler.is_active(FaultKind::motor_stall));
  EXPECT_EQ(scheduler.next_deadline(), SimTime(3500ms));
  scheduler.advance(4s, events);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].what, FaultEventKind::cleared);
  EXPECT_EQ(events[1].at, SimTime(3500ms));  // the time it ended, not when we looked
  EXPECT_EQ(events[1].reason, "expired");
  EXPECT_FALSE(scheduler.is_active(FaultKind::motor_stall));
}

TEST(FaultScheduler, OnNthActsOnThatRequestsReplyOnce) {
  FaultScheduler scheduler({spec_of(FaultKind::drop_reply, TriggerOnNth{kGetStatus, 3})}, 1);
  std::vector<FaultEvent> events;
  for (int i = 0; i < 2; ++i) {
    scheduler.on_request(1s, kGetStatus, Transport::tcp, events);
    EXPECT_FALSE(scheduler.take_wire_fault(1s, FaultKind::drop_reply, Transport::tcp, kGetStatus, events));
  }
  scheduler.on_request(1s, kGetProfile, Transport::tcp, events);  // other services do not count
  EXPECT_TRUE(events.empty());
  scheduler.on_request(1s, kGetStatus, Transport::tcp, events);
  // The trigger's service is the default filter: a profile does not use it up.
  EXPECT_FALSE(scheduler.take_wire_fault(1s, FaultKind::drop_reply, Transport::tcp, kGetProfile, events));
  const auto taken = scheduler.take_wire_fault(1s, FaultKind::drop_reply, Transport::tcp, kGetStatus, events);
  ASSERT_TRUE(taken);
  EXPECT_FALSE(scheduler.take_wire_fault(1s, FaultKind::drop_reply, Transport::tcp, kGetStatus, events));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].reason, "count used");
  for (int i = 0; i < 5; ++i) scheduler.on_request(2s, kGetStatus, Transport::tcp, events);
  EXPECT_EQ(events.size(), 2u) << "on: fires once";
}

TEST(FaultScheduler, EveryNthFiresPeriodically) {
  FaultSpec spec = spec_of(FaultKind::corrupt_checksum, TriggerEvery{kGetStatus, 4});
  FaultScheduler scheduler({spec}, 1);
  std::vector<FaultEvent> events;
  int hits = 0;
  for (int i = 1; i <= 12; ++i) {
    scheduler.on_request(1s, kGetStatus, Transport::serial, events);
    if (scheduler.take_wire_fault(1s, FaultKind::corrupt_checksum, Transport::serial, kGetStatus, events)) {
      ++hits;
      EXPECT_EQ(i % 4, 0) << i;
    }
  }
  EXPECT_EQ(hits, 3);
}

TEST(FaultScheduler, WireFaultRespectsTransportAndCount) {
  FaultSpec spec = spec_of(FaultKind::garbage);
  spec.transport = Transport::serial;
  spec.count = 2;
  FaultScheduler scheduler({}, 1);
  std::vector<FaultEvent> events;
  scheduler.inject(0s, spec, events);
  EXPECT_FALSE(scheduler.take_wire_fault(0s, FaultKind::garbage, Transport::tcp, kGetStatus, events));
  EXPECT_TRUE(scheduler.take_any_wire_fault(0s, Transport::serial, kGetStatus, events));
  EXPECT_TRUE(scheduler.take_any_wire_fault(0s, Transport::serial, kGetProfile, events));
  EXPECT_FALSE(scheduler.take_any_wire_fault(0s, Transport::serial, kGetStatus, events));
  // Device faults never come out as wire faults; corrupt_checksum never on CAN (D1 CRC per frame).
  scheduler.inject(0s, spec_of(FaultKind::motor_stall), events);
  scheduler.inject(0s, spec_of(FaultKind::corrupt_checksum), events);
  EXPECT_FALSE(scheduler.take_any_wire_fault(0s, Transport::can, kGetStatus, events));
}

TEST(FaultScheduler, ClearByIdAndAll) {
  FaultScheduler scheduler;
  std::vector<FaultEvent> events;
  const FaultId first = scheduler.inject(1s, spec_of(FaultKind::motor_stall), events);
  const FaultId second = scheduler.inject(1s, spec_of(FaultKind::window_dirt), events);
  EXPECT_NE(first, second);
  EXPECT_TRUE(scheduler.clear(2s, first, events));
  EXPECT_FALSE(scheduler.clear(2s, first, events));
  EXPECT_FALSE(scheduler.is_active(FaultKind::motor_stall));
  scheduler.clear_all(3s, "power cycle", events);
  EXPECT_TRUE(scheduler.active().empty());
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[3].reason, "power cycle");
}

TEST(FaultScheduler, ProbabilityIsCounterBasedAndDeterministic) {
  FaultSpec spec = spec_of(FaultKind::drop_reply, TriggerProbability{0.3});
  auto run = [&](std::uint64_t seed) {
    FaultScheduler scheduler({spec}, seed);
    std::vector<FaultEvent> events;
    std::vector<int> hits;
    for (int i = 0; i < 1000; ++i) {
      scheduler.on_request(SimTime(i), kGetStatus, Transport::tcp, events);
      if (scheduler.take_any_wire_fault(SimTime(i), Transport::tcp, kGetStatus, events)) hits.push_back(i);
    }
    return hits;
  };
  const auto a = run(7);
  EXPECT_EQ(a, run(7));
  EXPECT_NE(a, run(8));
  // 1000 draws at p = 0.3: 300 +- 6 sigma (sigma = 14.5).
  EXPECT_GT(a.size(), 213u);
  EXPECT_LT(a.size(), 387u);
  EXPECT_EQ(fault_draw(7, 0, 5), fault_draw(7, 0, 5));
  EXPECT_NE(fault_draw(7, 0, 5), fault_draw(7, 1, 5));
}

TEST(FaultScheduler, ControlInjectWithLaterTimeWaits) {
  FaultScheduler scheduler;
  std::vector<FaultEvent> events;
  EXPECT_EQ(scheduler.inject(1s, spec_of(FaultKind::encoder_error, TriggerAt{5s}), events), 0u);
  EXPECT_TRUE(events.empty());
  EXPECT_EQ(scheduler.next_deadline(), SimTime(5s));
  scheduler.advance(5s, events);
  EXPECT_TRUE(scheduler.is_active(FaultKind::encoder_error));
}

TEST(FaultScheduler, OneShotActsThenClears) {
  FaultScheduler scheduler({spec_of(FaultKind::power_cycle, TriggerAt{1s})}, 1);
  std::vector<FaultEvent> events;
  scheduler.advance(1s, events);
  const ActiveFault* fault = scheduler.find_active(FaultKind::power_cycle);
  ASSERT_NE(fault, nullptr);
  scheduler.acted(1s, fault->id, events);
  EXPECT_FALSE(scheduler.is_active(FaultKind::power_cycle));
  EXPECT_EQ(events.back().reason, "acted");
}

// A multi-frame ISO-TP request is seen at its first frame and again once complete; each trigger
// counts it once: isotp_fc_overflow's and isotp_fc_wait's at the first frame (they act there,
// on that very request), every other kind's when it is complete.
TEST(FaultScheduler, AMultiFrameRequestCountsOnceForEachTrigger) {
  constexpr std::uint16_t kSetFunction = 0x020A;
  FaultScheduler scheduler({spec_of(FaultKind::isotp_fc_overflow, TriggerOnNth{kSetFunction, 2}),
                            spec_of(FaultKind::drop_reply, TriggerOnNth{kSetFunction, 2})},
                           1);
  std::vector<FaultEvent> events;
  scheduler.on_request(0s, kSetFunction, Transport::can, events, RequestSeen::first_frame);
  scheduler.on_request(0s, kSetFunction, Transport::can, events, RequestSeen::rest_of_multi_frame);
  EXPECT_TRUE(events.empty());
  scheduler.on_request(1s, kSetFunction, Transport::can, events, RequestSeen::first_frame);
  ASSERT_EQ(events.size(), 1u);  // the second request's first frame: the overflow, for that frame
  EXPECT_EQ(events[0].kind, FaultKind::isotp_fc_overflow);
  // It acts on first frames of its trigger's service only.
  EXPECT_FALSE(scheduler.take_wire_fault(1s, FaultKind::isotp_fc_overflow, Transport::can, kGetStatus, events));
  EXPECT_TRUE(scheduler.take_wire_fault(1s, FaultKind::isotp_fc_overflow, Transport::can, kSetFunction, events));
  scheduler.on_request(2s, kSetFunction, Transport::can, events, RequestSeen::rest_of_multi_frame);
  ASSERT_EQ(events.size(), 3u);  // its one telegram used, then drop_reply when the request is complete
  EXPECT_EQ(events[1].reason, "count used");
  EXPECT_EQ(events[2].kind, FaultKind::drop_reply);
  EXPECT_EQ(events[2].what, FaultEventKind::injected);
  // A request in one piece counts for both.
  FaultScheduler whole({spec_of(FaultKind::isotp_fc_wait, TriggerOnNth{kSetFunction, 1}),
                        spec_of(FaultKind::drop_reply, TriggerOnNth{kSetFunction, 1})},
                       1);
  std::vector<FaultEvent> whole_events;
  whole.on_request(0s, kSetFunction, Transport::tcp, whole_events);
  EXPECT_EQ(whole_events.size(), 2u);
}

}  // namespace
}  // namespace ldoem::faults
