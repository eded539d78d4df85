// The fault-entry grammar shared by scene YAML and control-socket JSON (D11).
#include "ldoem/faults/fault_spec.hpp"

#include <gtest/gtest.h>

#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::faults {
namespace {

using namespace std::chrono_literals;
using Fields = std::vector<std::pair<std::string, FieldValue>>;

std::variant<FaultSpec, FieldError> build(const Fields& fields) {
  FaultEntryBuilder builder;
  for (const auto& [key, value] : fields) {
    if (auto problem = builder.set(key, value)) return *problem;
  }
  return builder.finish();
}

FaultSpec good(const Fields& fields) {
  auto result = build(fields);
  if (auto* problem = std::get_if<FieldError>(&result)) {
    ADD_FAILURE() << problem->key << ": " << problem->detail;
    return {};
  }
  return std::get<FaultSpec>(result);
}

FieldError bad(const Fields& fields) {
  auto result = build(fields);
  if (auto* problem = std::get_if<FieldError>(&result)) return *problem;
  ADD_FAILURE() << "accepted: " << describe(std::get<FaultSpec>(result));
  return {};
}

TEST(FaultCatalogue, EveryNameRoundTrips) {
  for (std::size_t i = 0; i < kFaultKindCount; ++i) {
    const auto kind = static_cast<FaultKind>(i);
    EXPECT_EQ(fault_kind_from_name(fault_name(kind)), kind);
    EXPECT_NE(std::string(all_fault_names()).find(fault_name(kind)), std::string::npos) << fault_name(kind);
  }
  EXPECT_FALSE(fault_kind_from_name("motor_stal"));
}

TEST(FaultCatalogue, TransportsFollowD11) {
  EXPECT_TRUE(applies_to(FaultKind::tcp_reset, Transport::tcp));
  EXPECT_FALSE(applies_to(FaultKind::tcp_reset, Transport::serial));
  EXPECT_TRUE(applies_to(FaultKind::isotp_drop_cf, Transport::can));
  EXPECT_FALSE(applies_to(FaultKind::corrupt_checksum, Transport::can));
  EXPECT_TRUE(applies_to(FaultKind::corrupt_checksum, Transport::serial));
  EXPECT_TRUE(applies_to(FaultKind::lpt_jam, Transport::lpt));
  EXPECT_FALSE(applies_to(FaultKind::motor_stall, Transport::tcp));
  EXPECT_EQ(info(FaultKind::motor_stall).fault_class, FaultClass::device);
  EXPECT_EQ(info(FaultKind::garbage).fault_class, FaultClass::wire);
}

TEST(FaultCatalogue, ExtentAndParametersFollowD11) {
  // Without duration_s or count: the link states last until cleared, other wire faults act once.
  for (FaultKind kind : {FaultKind::tcp_stall, FaultKind::bandwidth, FaultKind::isotp_fc_wait, FaultKind::can_silence,
                         FaultKind::lpt_jam, FaultKind::motor_stall, FaultKind::window_dirt}) {
    EXPECT_EQ(info(kind).extent, FaultExtent::until_cleared) << fault_name(kind);
  }
  for (FaultKind kind : {FaultKind::drop_reply, FaultKind::garbage, FaultKind::isotp_fc_overflow, FaultKind::lpt_lose_steps}) {
    EXPECT_EQ(info(kind).extent, FaultExtent::count_one) << fault_name(kind);
  }
  EXPECT_EQ(info(FaultKind::power_cycle).extent, FaultExtent::one_shot);
  EXPECT_TRUE(accepts(FaultKind::blind, FaultParam::sector_range));
  EXPECT_TRUE(accepts(FaultKind::blind, FaultParam::fraction));
  EXPECT_TRUE(accepts(FaultKind::window_dirt, FaultParam::fraction));
  EXPECT_FALSE(accepts(FaultKind::window_dirt, FaultParam::sector_range));
  EXPECT_TRUE(accepts(FaultKind::truncate_reply, FaultParam::bytes_kept));
  EXPECT_FALSE(accepts(FaultKind::drop_reply, FaultParam::delay_s));
}

TEST(FaultEntry, MinimalEntryIsNowAndUntilCleared) {
  const FaultSpec spec = good({{"kind", std::string("motor_stall")}});
  EXPECT_EQ(spec.kind, FaultKind::motor_stall);
  EXPECT_TRUE(std::holds_alternative<TriggerNow>(spec.trigger));
  EXPECT_FALSE(spec.duration);
  EXPECT_FALSE(spec.count);
}

TEST(FaultEntry, EveryTriggerAndParameter) {
  const FaultSpec at = good({{"kind", std::string("motor_stall")}, {"at_s", 2.5}, {"duration_s", 1.0}});
  EXPECT_EQ(std::get<TriggerAt>(at.trigger).at, 2500ms);
  EXPECT_EQ(at.duration, SimTime(1s));

  const FaultSpec on = good({{"on.service", std::string("GET_STATUS")}, {"on.nth", 3.0}, {"kind", std::string("drop_reply")}});
  EXPECT_EQ(std::get<TriggerOnNth>(on.trigger), (TriggerOnNth{0x0102, 3}));

  const FaultSpec every = good({{"kind", std::string("corrupt_checksum")}, {"every.service", std::string("get_profile")},
                                {"every.count", 10.0}, {"transport", std::string("serial")}});
  EXPECT_EQ(std::get<TriggerEvery>(every.trigger), (TriggerEvery{0x0301, 10}));
  EXPECT_EQ(every.transport, Transport::serial);

  const FaultSpec draw = good({{"kind", std::string("isotp_drop_cf")}, {"probability", 0.25}, {"count", 2.0}});
  EXPECT_EQ(std::get<TriggerProbability>(draw.trigger).probability, 0.25);
  EXPECT_EQ(draw.count, 2u);

  const FaultSpec blind = good({{"kind", std::string("blind")}, {"from_deg", 350.0}, {"to_deg", 10.0}});
  EXPECT_EQ(blind.from_ticks, 5600);
  EXPECT_EQ(blind.to_ticks, 160);

  const FaultSpec delay = good({{"kind", std::string("delay_reply")}, {"delay_s", 0.2}});
  EXPECT_EQ(delay.delay, 200ms);
  EXPECT_EQ(good({{"kind", std::string("power_cycle")}, {"off_s", 3.0}}).off, 3s);
  EXPECT_EQ(good({{"kind", std::string("truncate_reply")}, {"bytes_kept", 5.0}}).bytes_kept, 5u);
  EXPECT_EQ(good({{"kind", std::string("bandwidth")}, {"bytes_per_s", 300.0}}).bytes_per_s, 300u);
}

// The upper bounds themselves are accepted (docs/robustness.md).
TEST(FaultEntry, BoundsAreInclusive) {
  EXPECT_EQ(good({{"kind", std::string("garbage")}, {"bytes", 4096.0}}).garbage_bytes, kMaxGarbageBytes);
  EXPECT_EQ(good({{"kind", std::string("bandwidth")}, {"bytes_per_s", 125e6}}).bytes_per_s, kMaxBytesPerSecond);
  EXPECT_EQ(good({{"kind", std::string("delay_reply")}, {"delay_s", 60.0}}).delay, 60s);
  EXPECT_EQ(good({{"kind", std::string("drop_reply")}, {"count", 1e12}}).count, 1'000'000'000'000u);
}

TEST(FaultEntry, BadEntriesNameTheirKey) {
  struct Case {
    const char* title;
    Fields fields;
    FieldErrorKind kind;
    const char* key;
  };
  const std::vector<Case> cases{
      {"unknown kind", {{"kind", std::string("motor_fire")}}, FieldErrorKind::unknown_kind, "kind"},
      {"no kind", {{"at_s", 1.0}}, FieldErrorKind::missing_key, "kind"},
      {"negative time", {{"kind", std::string("motor_stall")}, {"at_s", -1.0}}, FieldErrorKind::out_of_range, "at_s"},
      {"zero duration", {{"kind", std::string("motor_stall")}, {"duration_s", 0.0}}, FieldErrorKind::out_of_range, "duration_s"},
      {"fraction over 1", {{"kind", std::string("window_dirt")}, {"fraction", 1.5}}, FieldErrorKind::out_of_range, "fraction"},
      {"probability over 1", {{"kind", std::string("drop_reply")}, {"probability", 2.0}}, FieldErrorKind::out_of_range, "probability"},
      {"unknown service", {{"kind", std::string("drop_reply")}, {"on.service", std::string("GET_COFFEE")}, {"on.nth", 1.0}},
       FieldErrorKind::unknown_service, "on.service"},
      {"reply is not a service", {{"kind", std::string("drop_reply")}, {"service", std::string("GET_STATUS reply")}},
       FieldErrorKind::unknown_service, "service"},
      {"nth 0", {{"kind", std::string("drop_reply")}, {"on.service", std::string("GET_STATUS")}, {"on.nth", 0.0}},
       FieldErrorKind::out_of_range, "on.nth"},
      {"on without nth", {{"kind", std::string("drop_reply")}, {"on.service", std::string("GET_STATUS")}},
       FieldErrorKind::missing_key, "on.nth"},
      {"two triggers", {{"kind", std::string("drop_reply")}, {"at_s", 1.0}, {"probability", 0.5}},
       FieldErrorKind::conflicting_keys, ""},
      {"duration and count", {{"kind", std::string("drop_reply")}, {"duration_s", 1.0}, {"count", 2.0}},
       FieldErrorKind::conflicting_keys, "count"},
      {"parameter of another kind", {{"kind", std::string("drop_reply")}, {"fraction", 0.5}}, FieldErrorKind::unknown_key, "fraction"},
      {"transport it has not", {{"kind", std::string("tcp_reset")}, {"transport", std::string("can")}},
       FieldErrorKind::conflicting_keys, "transport"},
      {"device fault with transport", {{"kind", std::string("motor_stall")}, {"transport", std::string("tcp")}},
       FieldErrorKind::conflicting_keys, "transport"},
      {"text for a number", {{"kind", std::string("motor_stall")}, {"at_s", std::string("soon")}}, FieldErrorKind::wrong_type, "at_s"},
      {"fractional count", {{"kind", std::string("drop_reply")}, {"count", 1.5}}, FieldErrorKind::wrong_type, "count"},
      {"blind without sector", {{"kind", std::string("blind")}}, FieldErrorKind::conflicting_keys, ""},
      {"blind half a sector", {{"kind", std::string("blind")}, {"from_deg", 10.0}}, FieldErrorKind::missing_key, "to_deg"},
      {"one-shot with duration", {{"kind", std::string("power_cycle")}, {"duration_s", 1.0}},
       FieldErrorKind::conflicting_keys, "duration_s"},
      {"unknown key", {{"kind", std::string("motor_stall")}, {"colour", 1.0}}, FieldErrorKind::unknown_key, "colour"},
      {"unknown trigger member", {{"kind", std::string("drop_reply")}, {"on.nht", 1.0}}, FieldErrorKind::unknown_key, "on.nht"},
      // Issue 27 D1, D2: the values that size memory or time have upper bounds.
      {"garbage of 4 GiB", {{"kind", std::string("garbage")}, {"bytes", 4294967295.0}}, FieldErrorKind::out_of_range, "bytes"},
      {"garbage over 4096", {{"kind", std::string("garbage")}, {"bytes", 4097.0}}, FieldErrorKind::out_of_range, "bytes"},
      {"bandwidth over 1 Gbit/s", {{"kind", std::string("bandwidth")}, {"bytes_per_s", 125000001.0}},
       FieldErrorKind::out_of_range, "bytes_per_s"},
      {"delay over 60 s", {{"kind", std::string("delay_reply")}, {"delay_s", 61.0}}, FieldErrorKind::out_of_range, "delay_s"},
      {"delay of 1e6 s", {{"kind", std::string("delay_reply")}, {"delay_s", 1e6}}, FieldErrorKind::out_of_range, "delay_s"},
      {"count over 1e12", {{"kind", std::string("drop_reply")}, {"count", 1e13}}, FieldErrorKind::out_of_range, "count"},
      {"duration over 1e6 s", {{"kind", std::string("tcp_stall")}, {"duration_s", 2e6}}, FieldErrorKind::out_of_range, "duration_s"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.title);
    const FieldError problem = bad(c.fields);
    EXPECT_EQ(problem.kind, c.kind) << problem.detail;
    EXPECT_EQ(problem.key, c.key) << problem.detail;
    EXPECT_FALSE(problem.detail.empty());
  }
}

TEST(FaultEntry, DescribeNamesKindAndTrigger) {
  const FaultSpec spec = good({{"kind", std::string("drop_reply")}, {"on.service", std::string("GET_STATUS")}, {"on.nth", 2.0}});
  EXPECT_EQ(describe(spec), "drop_reply on=GET_STATUS#2");
}

}  // namespace
}  // namespace ldoem::faults
