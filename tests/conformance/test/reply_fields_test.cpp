// reply_fields / compare_fields: telegrams as named fields, differences by name, masks.
#include <gtest/gtest.h>

#include "ldoem/protocol/messages.hpp"
#include "options.hpp"
#include "reply_fields.hpp"

namespace ldoem::conformance {
namespace {

namespace p = protocol;

std::string value_of(const std::vector<NamedField>& fields, const std::string& name) {
  for (const auto& field : fields) {
    if (field.name == name) return field.value;
  }
  return "(none)";
}

p::Bytes profile_payload(std::uint16_t t_start, std::uint16_t distance) {
  p::Profile profile;
  profile.format = p::kFormatRangeEcho;
  profile.profile_sent = 1;
  profile.profile_count = 7;
  p::SectorBlock block;
  block.t_start_ms = t_start;
  block.points = {{256, 0, 10}, {distance, 0, 20}};
  profile.sectors = {block};
  profile.status = p::make_status_block(p::SensorMode::measure, p::MotorMode::ok);
  return p::encode_response(profile);
}

TEST(ReplyFields, StatusReply_HasNamedNibbles) {
  const auto fields = reply_fields(p::Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x93});
  EXPECT_EQ(value_of(fields, "service"), "GET_STATUS reply");
  EXPECT_EQ(value_of(fields, "status.sensor_mode"), "3");
  EXPECT_EQ(value_of(fields, "status.motor_mode"), "0x0009");
}

TEST(ReplyFields, ProfileAndFailure_HaveTheirFields) {
  const auto fields = reply_fields(profile_payload(100, 512));
  EXPECT_EQ(value_of(fields, "profile.count"), "7");
  EXPECT_EQ(value_of(fields, "profile.sector0.points"), "2");
  EXPECT_EQ(value_of(fields, "profile.sector0.point1.distance"), "512");
  EXPECT_EQ(value_of(fields, "profile.senstat.sensor_mode"), "3");
  const auto failure = reply_fields(p::Bytes{0xFF, 0x00, 0x03, 0x01, 0x00, 0x03});
  EXPECT_EQ(value_of(failure, "failure.request"), "0x0301");
  EXPECT_EQ(value_of(failure, "failure.reason"), "3");
  EXPECT_EQ(value_of(reply_fields(p::Bytes{0x82, 0x05, 0x12, 0x34}), "get_sync_clock.clock_ms"), "4660");
  EXPECT_EQ(value_of(reply_fields(p::Bytes{0x01, 0x02}), "undecodable"), "0102");
}

TEST(CompareFields, NamesTheDifferingFieldOnly) {
  const auto diff = compare_fields(reply_fields(profile_payload(100, 512)), reply_fields(profile_payload(100, 513)), {});
  ASSERT_EQ(diff.size(), 1u);
  EXPECT_EQ(diff[0].name, "profile.sector0.point1.distance");
  EXPECT_EQ(diff[0].recorded, "512");
  EXPECT_EQ(diff[0].live, "513");
}

TEST(CompareFields, MasksLeaveFieldsOut) {
  const auto recorded = reply_fields(profile_payload(100, 512));
  const auto live = reply_fields(profile_payload(250, 512));
  EXPECT_EQ(compare_fields(recorded, live, {}).size(), 1u);
  EXPECT_TRUE(compare_fields(recorded, live, kTimeFieldMasks).empty());
  EXPECT_TRUE(compare_fields(recorded, live, {"profile.*.tstart"}).empty());
}

TEST(CompareFields, DifferentServices_ShowAbsentFields) {
  const auto diff = compare_fields(reply_fields(p::Bytes{0x81, 0x02, 0, 0, 0, 1}),
                                   reply_fields(p::Bytes{0xFF, 0x00, 0x01, 0x02, 0x00, 0x03}), {});
  ASSERT_FALSE(diff.empty());
  EXPECT_EQ(diff[0].name, "service");
  bool saw_absent = false;
  for (const auto& d : diff) saw_absent |= d.live == "(absent)" || d.recorded == "(absent)";
  EXPECT_TRUE(saw_absent);
}

}  // namespace
}  // namespace ldoem::conformance
