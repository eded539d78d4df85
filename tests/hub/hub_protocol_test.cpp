#include "ldoem/hub/hub_protocol.hpp"

#include <gtest/gtest.h>

namespace ldoem::hub {
namespace {

using std::chrono::milliseconds;

struct RequestRow {
  const char* line;
  HubRequest request;
};

const std::vector<RequestRow>& request_table() {
  static const std::vector<RequestRow> rows{
      {"1 left INITIALIZE", {"1", "left", InitializeRequest{}}},
      {"a.7 left INITIALIZE speed=10 step=4 sectors=3:160,1:5596",
       {"a.7", "left", InitializeRequest{10, 4, {{3, 160}, {1, 5596}}}}},
      {"2 left ROTATE", {"2", "left", RotateCommand{}}},
      {"3 left ROTATE 15", {"3", "left", RotateCommand{15}}},
      {"4 left MEASURE", {"4", "left", MeasureCommand{}}},
      {"5 left IDLE", {"5", "left", IdleCommand{}}},
      {"6 left GET2DPROFILE", {"6", "left", ProfileCommand{}}},
      {"7 left GET2DPROFILE 0", {"7", "left", ProfileCommand{milliseconds(0)}}},
      {"8 left MOVEMOTOR 120 down full", {"8", "left", MotorMove{120, TiltDirection::decreasing, StepMode::full_step, {}}}},
      {"9 left MOVEMOTOR 2 up half 400", {"9", "left", MotorMove{2, TiltDirection::increasing, StepMode::half_step, 400.0}}},
      {"10 right STATUS", {"10", "right", StatusCommand{}}},
      {"11 right STATUS 250", {"11", "right", StatusCommand{milliseconds(250)}}},
      {"12 * DEVICES", {"12", "*", DevicesCommand{}}},
  };
  return rows;
}

TEST(HubRequest, Table_ParsesAndFormatsBothWays) {
  for (const RequestRow& row : request_table()) {
    auto parsed = parse_request(row.line);
    ASSERT_TRUE(parsed) << row.line << ": " << parsed.error().detail;
    EXPECT_EQ(*parsed, row.request) << row.line;
    EXPECT_EQ(format_request(row.request), row.line);
  }
}

TEST(HubRequest, CrLfAndExtraSpaces_AreAccepted) {
  auto parsed = parse_request("  x1   left   STATUS \r\n");
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->id, "x1");
}

TEST(HubRequest, BadLines_NameTheirIdWhenTheyHaveOne) {
  struct Row {
    const char* line;
    const char* id;
    const char* kind;
  };
  const Row rows[] = {
      {"", "-", "bad_request"},
      {"!! left STATUS", "-", "bad_request"},
      {"5 left", "5", "bad_request"},
      {"5 left JUMP", "5", "unknown_command"},
      {"5 left ROTATE fast", "5", "bad_request"},
      {"5 left MOVEMOTOR 3 sideways full", "5", "bad_request"},
      {"5 left MOVEMOTOR 3 up quarter", "5", "bad_request"},
      {"5 left MOVEMOTOR -3 up full", "5", "bad_request"},
      {"5 left MOVEMOTOR 3 up full 0", "5", "bad_request"},
      {"5 left MEASURE now", "5", "bad_request"},
      {"5 left INITIALIZE sectors=3", "5", "bad_request"},
      {"5 left DEVICES", "5", "bad_request"},
      {"5 * STATUS", "5", "bad_request"},
      {"5 l/r STATUS", "5", "bad_request"},
  };
  for (const Row& row : rows) {
    auto parsed = parse_request(row.line);
    ASSERT_FALSE(parsed) << row.line;
    EXPECT_EQ(parsed.error().id, row.id) << row.line;
    EXPECT_EQ(parsed.error().kind, row.kind) << row.line;
  }
}

TEST(HubReply, OkAndErr_RoundTrip) {
  const HubReply ok = ok_reply("7", "INITIALIZE", {{"ident.0001", "LD OEM 1000"}, {"pct", "100%"}, {"eq", "a=b"}});
  const std::string line = format_reply(ok);
  EXPECT_EQ(line, "7 OK INITIALIZE ident.0001=LD%20OEM%201000 pct=100%25 eq=a=b");
  auto back = parse_reply(line);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, ok);

  const HubReply err = error_reply("8", "timeout", "left (B1): GET_STATUS tcp:x: timeout");
  auto err_back = parse_reply(format_reply(err));
  ASSERT_TRUE(err_back);
  EXPECT_EQ(*err_back, err);
}

TEST(HubReply, Garbage_IsAnError) {
  EXPECT_FALSE(parse_reply("7 ERR busy two\nlines"));  // fuzz_hub_request: not a line
  EXPECT_FALSE(parse_reply("7 MAYBE STATUS"));
  EXPECT_FALSE(parse_reply("7 OK STATUS novalue"));
  EXPECT_FALSE(parse_reply("7 OK STATUS a=%4"));
  EXPECT_FALSE(parse_reply("7"));
}

TEST(HubReply, TypedFields_RoundTrip) {
  const StatusBlock status = protocol::make_status_block(protocol::SensorMode::measure, protocol::MotorMode::ok);
  HubReply reply = ok_reply("1", "STATUS", status_fields(status));
  EXPECT_EQ(reply.field("status"), "00000003");
  EXPECT_EQ(reply.field("mode"), "measure");
  EXPECT_EQ(status_from(reply), status);

  protocol::Profile profile;
  profile.format = protocol::kFormatRangeEcho;
  profile.profile_sent = 1;
  profile.profile_count = 9;
  protocol::SectorBlock block;
  block.dir_step_ticks = 4;
  block.points = {{512, 0, 3}, {0, 0, 0}};
  profile.sectors.push_back(block);
  profile.status = status;
  const ProfileSample sample{profile, TiltPosition{-240}};
  auto sample_back = profile_from(parse_reply(format_reply(ok_reply("2", "GET2DPROFILE", profile_fields(sample)))).value());
  ASSERT_TRUE(sample_back);
  EXPECT_EQ(*sample_back, sample);
  EXPECT_DOUBLE_EQ(sample_back->tilt.tilt_deg(), -10.8);

  const DeviceInfo info{status, {{0x0001, "LD-OEM1000"}, {0x0012, "1.2 beta"}}};
  auto info_back = info_from(parse_reply(format_reply(ok_reply("3", "INITIALIZE", info_fields(info)))).value());
  ASSERT_TRUE(info_back);
  EXPECT_EQ(*info_back, info);
}

TEST(ErrorKindToken, EveryKind_RoundTrips) {
  for (int k = 0; k <= static_cast<int>(ErrorKind::wrong_state); ++k) {
    const auto kind = static_cast<ErrorKind>(k);
    EXPECT_EQ(error_kind_from_token(error_kind_token(kind)), kind);
  }
  EXPECT_EQ(error_kind_from_token("unknown_device"), ErrorKind::invalid_argument);
}

}  // namespace
}  // namespace ldoem::hub
