// decode_response beyond the spec 7.2 rows: SERVICE_FAILURE, GET_CONFIG by echoed key, lengths.
#include "ldoem/protocol/messages.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::hex;

TEST(ServiceFailureReply, Encode_IsFF00CodeReason) {
  EXPECT_EQ(encode_response(ServiceFailure{0x0402, FailureReason::wrong_state}), hex("FF 00 04 02 00 03"));
  const auto decoded = decode_response(hex("FF 00 00 00 00 05"));
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(*decoded, Response{(ServiceFailure{0x0000, FailureReason::framing})});
}

TEST(ServiceFailureReply, FromRequestError_CopiesCodeAndReason) {
  const auto error = decode_request(hex("04 03"));
  ASSERT_FALSE(error.has_value());
  EXPECT_EQ(encode_response(failure_reply(error.error())), hex("FF 00 04 03 00 02"));
}

TEST(SetFunctionReply, Success_EchoesSectorPerD3) {
  EXPECT_EQ(encode_response(SetFunctionReply{3}), hex("82 0A 00 03"));
}

TEST(GetConfigReply, DecodesByEchoedKey) {
  const auto serial = decode_response(hex("82 02 00 01 00 06 00 00 00 01 00 08"));
  ASSERT_TRUE(serial.has_value());
  EXPECT_EQ(*serial, (Response{GetConfigReply{SerialConfig{6, 0, 1, 8}}}));
  const auto can = decode_response(hex("82 02 00 02 00 04 06 C0 06 C1 00 00 00 00"));
  ASSERT_TRUE(can.has_value());
  EXPECT_EQ(*can, (Response{GetConfigReply{CanConfig{}}}));
}

TEST(GetConfigReply, GlobalWithPad_IsBadLength) {
  // The S2 pad is a request quirk; a reply has exactly the key's fields.
  const auto decoded = decode_response(hex("82 02 00 10 00 01 00 0A 00 08 00 00"));
  ASSERT_FALSE(decoded.has_value());
  EXPECT_EQ(decoded.error(), DecodeError::bad_length);
}

TEST(GetConfigReply, UnknownKey_IsUnknownConfigKey) {
  const auto decoded = decode_response(hex("82 02 00 04 00 00"));
  ASSERT_FALSE(decoded.has_value());
  EXPECT_EQ(decoded.error(), DecodeError::unknown_config_key);
}

TEST(GetStatusReply, UnpublishedTrailingFields_AreKept) {
  const Bytes payload = hex("81 02 00 00 00 23 12 34");
  const auto decoded = decode_response(payload);
  ASSERT_TRUE(decoded.has_value());
  const auto& reply = std::get<GetStatusReply>(*decoded);
  // Motor nibble 2 is not in spec 2.4: kept raw, and flagged as unknown.
  EXPECT_EQ(reply.status.status.sensor, SensorMode::measure);
  EXPECT_EQ(reply.status.status.to_byte(), 0x23);
  EXPECT_FALSE(reply.status.status.is_known());
  EXPECT_EQ(reply.unpublished_fields, hex("12 34"));
  EXPECT_EQ(encode_response(*decoded), payload);
}

TEST(IdentificationReply, StopsAtNul_SerialPadding) {
  const auto decoded = decode_response(hex("81 01 30 2E 31 2E 30 00"));
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(*decoded, Response{IdentificationReply{"0.1.0"}});
  EXPECT_EQ(encode_response(IdentificationReply{"0.1.0"}), hex("81 01 30 2E 31 2E 30"));  // D3: no NUL
}

struct BadReply {
  const char* title;
  const char* payload_hex;
  DecodeError expected;
};

class DecodeResponseFailure : public ::testing::TestWithParam<BadReply> {};

TEST_P(DecodeResponseFailure, NamesTheProblem) {
  const auto decoded = decode_response(hex(GetParam().payload_hex));
  ASSERT_FALSE(decoded.has_value()) << GetParam().title;
  EXPECT_EQ(decoded.error(), GetParam().expected) << GetParam().title;
}

INSTANTIATE_TEST_SUITE_P(
    Replies, DecodeResponseFailure,
    ::testing::Values(BadReply{"empty", "", DecodeError::truncated},
                      BadReply{"a request code", "01 02", DecodeError::unknown_service},
                      BadReply{"unknown reply", "85 01 00 00", DecodeError::unknown_service},
                      BadReply{"unpublished reply", "86 01 00 00", DecodeError::unknown_service},
                      BadReply{"GET_STATUS short", "81 02 00 00 00", DecodeError::bad_length},
                      BadReply{"TRANS_IDLE long", "84 02 00 00 00 01 00 00", DecodeError::bad_length},
                      BadReply{"TRANS_MEASURE without code", "84 04 00 00 00 03", DecodeError::bad_length},
                      BadReply{"SET_CONFIG without result", "82 01", DecodeError::bad_length},
                      BadReply{"GET_FUNCTION short", "82 0B 00 00 00 03", DecodeError::bad_length},
                      BadReply{"GET_CONFIG without key", "82 02", DecodeError::bad_length},
                      BadReply{"SERVICE_FAILURE short", "FF 00 01 02", DecodeError::bad_length}));

TEST(ResponseCode, EveryReply_CarriesBit15OrFF00) {
  EXPECT_EQ(response_code_of(Response{TransMeasureReply{}}), 0x8404);
  EXPECT_EQ(response_code_of(Response{Profile{}}), 0x8301);
  EXPECT_EQ(response_code_of(Response{SetFunctionReply{}}), 0x820A);
  EXPECT_EQ(response_code_of(Response{ServiceFailure{}}), 0xFF00);
}

}  // namespace
}  // namespace ldoem::protocol
