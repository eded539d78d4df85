// Every golden vector of spec 7.1, 7.2, 7.4 and 7.5 (tests/vectors/spec-section7.yaml), byte for
// byte in both directions: typed message -> bytes, and bytes -> deframer -> typed message.
#include <yaml-cpp/yaml.h>

#include <map>
#include <optional>
#include <string>

#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::hex;

YAML::Node spec_vectors() { return YAML::LoadFile(LDOEM_SPEC_VECTORS_PATH); }

GlobalConfig global(std::uint16_t id, std::uint16_t hz, std::uint16_t step, bool pad = false) {
  return GlobalConfig{id, hz, step, pad};
}

// Spec 7.1: what each named request means.
const std::map<std::string, Request>& tcp_request_meanings() {
  static const std::map<std::string, Request> meanings{
      {"GET_IDENTIFICATION 0x00", GetIdentification{0x00}},
      {"GET_IDENTIFICATION 0x01", GetIdentification{0x01}},
      {"GET_IDENTIFICATION 0x02", GetIdentification{0x02}},
      {"GET_IDENTIFICATION 0x03", GetIdentification{0x03}},
      {"GET_IDENTIFICATION 0x04", GetIdentification{0x04}},
      {"GET_IDENTIFICATION 0x10", GetIdentification{0x10}},
      {"GET_IDENTIFICATION 0x11", GetIdentification{0x11}},
      {"GET_IDENTIFICATION 0x12", GetIdentification{0x12}},
      {"GET_IDENTIFICATION 0x20", GetIdentification{0x20}},
      {"GET_IDENTIFICATION 0x21", GetIdentification{0x21}},
      {"GET_IDENTIFICATION 0x22", GetIdentification{0x22}},
      {"GET_STATUS", GetStatus{}},
      {"GET_SIGNAL", GetSignal{}},
      {"SET_SIGNAL 0x00", SetSignal{0x00}},
      {"SET_SIGNAL 0x11 (yellow A + switch 0)", SetSignal{0x11}},
      {"SET_CONFIG global id 1, 10 Hz, 0.5°", SetConfig{global(1, 10, 8)}},
      {"GET_CONFIG global", GetConfig{0x0010}},
      {"GET_CONFIG Ethernet", GetConfig{0x0005}},
      {"SET_TIME_ABS 1000 ms", SetTimeAbs{1000}},
      {"SET_TIME_REL −10 ms", SetTimeRel{-10}},
      {"GET_SYNC_CLOCK", GetSyncClock{}},
      {"SET_FILTER near-field on", SetFilter{1, 1}},
      {"SET_FILTER near-field off", SetFilter{1, 0}},
      {"SET_FUNCTION s0 normal 270° temp", SetFunction{0, 3, 270 * 16, 0}},
      {"SET_FUNCTION s1 no-meas 314.5° temp", SetFunction{1, 1, 3145 * 16 / 10, 0}},
      {"SET_FUNCTION s2 normal 45° temp", SetFunction{2, 3, 45 * 16, 0}},
      {"SET_FUNCTION s3 no-meas 89.5° temp", SetFunction{3, 1, 895 * 16 / 10, 0}},
      {"SET_FUNCTION s4 not-init 0 temp", SetFunction{4, 0, 0, 0}},
      {"GET_FUNCTION s0", GetFunction{0}},
      {"GET_FUNCTION s7", GetFunction{7}},
      {"GET_PROFILE stream 0x39FF", GetProfile{0, 0x39FF}},
      {"GET_PROFILE stream 0x3DFF", GetProfile{0, 0x3DFF}},
      {"GET_PROFILE 1 × 0x39FF", GetProfile{1, 0x39FF}},
      {"CANCEL_PROFILE", CancelProfile{}},
      {"DO_RESET level 0", DoReset{0}},
      {"DO_RESET level 1", DoReset{1}},
      {"DO_RESET level 2", DoReset{2}},
      {"TRANS_IDLE", TransIdle{}},
      {"TRANS_ROTATE (flash speed)", TransRotate{0}},
      {"TRANS_ROTATE 10 Hz (layout per S1, non-zero value per S2's semantics)", TransRotate{10}},
      {"TRANS_MEASURE", TransMeasure{}},
  };
  return meanings;
}

StatusBlock block(SensorMode sensor) { return make_status_block(sensor, MotorMode::ok); }

Profile range_profile_example() {
  Profile profile;
  profile.format = 0x39FF;
  profile.profile_sent = 1;
  profile.profile_count = 100;
  SectorBlock sector;
  sector.dir_step_ticks = 8;
  sector.t_start_ms = 0x1234;
  sector.points = {{0x0100, 0, 0}, {0x0280, 0, 0}, {0, 0, 0}};  // 1 m, 2.5 m, no echo
  sector.t_end_ms = 0x1236;
  sector.end_dir_ticks = 16;
  profile.sectors = {sector};
  profile.status = block(SensorMode::measure);
  return profile;
}

Profile echo_profile_example() {
  Profile profile = range_profile_example();
  profile.format = 0x3DFF;
  auto& sector = profile.sectors[0];
  sector.start_dir_ticks = 180 * 16;
  sector.points = {{0x0100, 0, 200}, {0x0280, 0, 80}};
  sector.t_end_ms = 0x1235;
  sector.end_dir_ticks = 1805 * 16 / 10;
  return profile;
}

// Spec 7.2: what each named reply means.
const std::map<std::string, Response>& tcp_reply_meanings() {
  static const std::map<std::string, Response> meanings{
      {"GET_STATUS, IDLE, motor OK", GetStatusReply{block(SensorMode::idle), {}}},
      {"GET_STATUS, MEASURE, motor OK", GetStatusReply{block(SensorMode::measure), {}}},
      {"TRANS_IDLE → IDLE", TransIdleReply{block(SensorMode::idle)}},
      {"TRANS_ROTATE → ROTATE, motor OK", TransRotateReply{block(SensorMode::rotate)}},
      {"TRANS_MEASURE OK", TransMeasureReply{block(SensorMode::measure), measure_return::kOk}},
      {"TRANS_MEASURE refused, code 2",
       TransMeasureReply{block(SensorMode::rotate), measure_return::kMeanPulseFrequencyTooHigh}},
      {"CANCEL_PROFILE, MEASURE", CancelProfileReply{block(SensorMode::measure)}},
      {"GET_CONFIG global (1, 10 Hz, 8 ticks)", GetConfigReply{global(1, 10, 8)}},
      {"GET_CONFIG Ethernet 192.168.1.10/255.255.255.0/192.168.1.1, node 0, port 0",
       GetConfigReply{EthernetConfig{{192, 168, 1, 10}, {255, 255, 255, 0}, {192, 168, 1, 1}, 0, 0}}},
      {"SET_CONFIG success", SetConfigReply{kSetConfigSuccess}},
      {"GET_FUNCTION s0 normal 270°", GetFunctionReply{0, 3, 270 * 16}},
      {"GET_FUNCTION s1 not initialised", GetFunctionReply{1, 0, 0}},
      {"SET_FUNCTION invalid", SetFunctionReply{kSetFunctionInvalid}},
      {"SET_SIGNAL accepted", SetSignalReply{0}},
      {"GET_SIGNAL port 0x01", GetSignalReply{0x01}},
      {"GET_SYNC_CLOCK 0x1234 ms", SyncClockReply{0x1234}},
      {"SET_TIME_ABS → 1000 ms", SetTimeAbsReply{1000}},
      {"DO_RESET level 2", DoResetReply{2}},
      {"SET_FILTER item 1", SetFilterReply{1}},
      {"GET_IDENTIFICATION, text 'LD-OEM' (text illustrative)", IdentificationReply{"LD-OEM"}},
      {"Profile 0x39FF: sent 1, count 100, layer 0, sector 0, step 0.5°, 3 points, t 0x1234→0x1236 ms, "
       "0°→1°, distances 1 m / 2.5 m / 0",
       range_profile_example()},
      {"Profile 0x3DFF: same header, 2 points at 180°/180.5°, (1 m, echo 200), (2.5 m, echo 80)",
       echo_profile_example()},
  };
  return meanings;
}

// Spec 7.4: what each named serial request means; nullopt where the telegram is refused.
const std::map<std::string, std::optional<Request>>& serial_request_meanings() {
  static const std::map<std::string, std::optional<Request>> meanings{
      {"GET_IDENTIFICATION item 1 (S2's default)", GetIdentification{1}},
      {"GET_IDENTIFICATION item 0", GetIdentification{0}},
      {"GET_STATUS", GetStatus{}},
      {"GET_SIGNAL", GetSignal{}},
      {"SET_SIGNAL 0x0001", SetSignal{1}},
      {"SET_CONFIG RS-232 115200 8N1", SetConfig{SerialConfig{6, 0, 1, 8}}},
      {"SET_CONFIG global id 0x10, 10 Hz, 0.5°, pad 0", SetConfig{global(0x10, 10, 8, true)}},
      {"GET_CONFIG key 1 (S2's LEN 6)", std::nullopt},  // LLLL 6 for 4 WORDs: bad_length
      {"GET_CONFIG key 1 (LEN by the rule)", GetConfig{1}},
      {"SET_TIME_ABS 0", SetTimeAbs{0}},
      {"GET_SYNC_CLOCK", GetSyncClock{}},
      {"SET_FUNCTION s0 normal 359° flash", SetFunction{0, 3, 359 * 16, 1}},
      {"SET_FUNCTION s1 not-init stop 0xFFF0 flash", SetFunction{1, 0, 0xFFF0, 1}},
      {"GET_FUNCTION s1", GetFunction{1}},
      {"GET_PROFILE 1 × 0x0700", GetProfile{1, 0x0700}},
      {"GET_PROFILE stream 0x0300", GetProfile{0, 0x0300}},
      {"CANCEL_PROFILE (+ 0x0000)", CancelProfile{true}},
      {"DO_RESET 2", DoReset{2}},
      {"TRANS_IDLE (+ 0x0000)", TransIdle{true}},
      {"TRANS_ROTATE 15 Hz", TransRotate{15}},
      {"TRANS_ROTATE 5 Hz", TransRotate{5}},
      {"TRANS_MEASURE (+ 0x0000)", TransMeasure{true}},
  };
  return meanings;
}

Bytes tcp_payload_of(const Bytes& frame) {
  return Bytes(frame.begin() + kTcpHeaderSize, frame.end() - kTcpTrailerSize);
}

TEST(SpecVectors, FileHasEverySection_NonEmpty) {
  const auto vectors = spec_vectors();
  EXPECT_EQ(vectors["tcp_requests"].size(), tcp_request_meanings().size());
  EXPECT_EQ(vectors["tcp_replies"].size(), tcp_reply_meanings().size());
  EXPECT_EQ(vectors["serial_requests"].size(), serial_request_meanings().size());
  EXPECT_EQ(vectors["algorithms"].size(), 6u);
}

TEST(SpecVectors, TcpRequests_EncodeAndDecodeByteForByte) {
  for (const auto& row : spec_vectors()["tcp_requests"]) {
    const auto name = row["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto meaning = tcp_request_meanings().find(name);
    ASSERT_NE(meaning, tcp_request_meanings().end()) << "no typed meaning for this row";
    const Bytes frame = hex(row["frame"].as<std::string>());

    EXPECT_EQ(encode_tcp_frame(encode_request(meaning->second)), frame);

    test::expect_events_every_split([] { return TcpDeframer(); }, frame,
                                    {test::telegram(tcp_payload_of(frame))});
    const auto decoded = decode_request(tcp_payload_of(frame));
    ASSERT_TRUE(decoded.has_value()) << describe(decoded.error().detail);
    EXPECT_EQ(*decoded, meaning->second);
  }
}

TEST(SpecVectors, TcpReplies_EncodeAndDecodeByteForByte) {
  for (const auto& row : spec_vectors()["tcp_replies"]) {
    const auto name = row["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto meaning = tcp_reply_meanings().find(name);
    ASSERT_NE(meaning, tcp_reply_meanings().end()) << "no typed meaning for this row";
    const Bytes frame = hex(row["frame"].as<std::string>());

    EXPECT_EQ(encode_tcp_frame(encode_response(meaning->second)), frame);

    test::expect_events_every_split([] { return TcpDeframer(); }, frame,
                                    {test::telegram(tcp_payload_of(frame))});
    const auto decoded = decode_response(tcp_payload_of(frame));
    ASSERT_TRUE(decoded.has_value()) << describe(decoded.error());
    EXPECT_EQ(*decoded, meaning->second);
  }
}

TEST(SpecVectors, SerialRequests_EncodeAndDecodeByteForByte) {
  for (const auto& row : spec_vectors()["serial_requests"]) {
    const auto name = row["name"].as<std::string>();
    SCOPED_TRACE(name);
    const auto meaning = serial_request_meanings().find(name);
    ASSERT_NE(meaning, serial_request_meanings().end()) << "no typed meaning for this row";
    const auto body = row["ascii"].as<std::string>();
    const Bytes wire = test::serial_wire(body);

    // The table's LEN and CRC columns agree with the telegram text.
    EXPECT_EQ(std::stoul(body.substr(4, 4), nullptr, 16), row["length_word"].as<unsigned>());
    EXPECT_EQ(std::stoul(body.substr(body.size() - 4), nullptr, 16),
              std::stoul(row["crc"].as<std::string>(), nullptr, 16));

    if (!meaning->second) {
      test::expect_events_every_split([] { return SerialDeframer(); }, wire,
                                      {test::framing_error(DecodeError::bad_length, 0x0202)});
      continue;
    }
    EXPECT_EQ(encode_serial_request(encode_request(*meaning->second)), wire);

    const Bytes payload = encode_request(*meaning->second);
    test::expect_events_every_split([] { return SerialDeframer(); }, wire, {test::telegram(payload)});
    SerialDeframer deframer;
    const auto events = deframer.feed(wire);
    ASSERT_EQ(events.size(), 1u);
    ASSERT_TRUE(std::holds_alternative<Telegram>(events[0]));
    const auto decoded = decode_request(std::get<Telegram>(events[0]).payload);
    ASSERT_TRUE(decoded.has_value()) << describe(decoded.error().detail);
    EXPECT_EQ(*decoded, *meaning->second);
  }
}

TEST(SpecVectors, Algorithms_MatchSection75) {
  for (const auto& row : spec_vectors()["algorithms"]) {
    const auto name = row["name"].as<std::string>();
    const auto expected = std::stoul(row["output"].as<std::string>(), nullptr, 16);
    const Bytes input = row["input_ascii"] ? test::ascii(row["input_ascii"].as<std::string>())
                                           : hex(row["input"].as<std::string>());
    SCOPED_TRACE(name + " of " + format_telegram(input));
    if (name == "xor_checksum") {
      EXPECT_EQ(xor_checksum(input), expected);
    } else if (name == "serial_crc_register_form") {
      EXPECT_EQ(serial_crc(input), expected);
    } else {
      ADD_FAILURE() << "unknown algorithm row";
    }
  }
}

}  // namespace
}  // namespace ldoem::protocol
