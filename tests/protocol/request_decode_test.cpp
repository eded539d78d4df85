// decode_request's D2 failure paths: every refusal carries the REQUEST_CODE and REASON that
// SERVICE_FAILURE answers with, plus the exact detail.
#include "ldoem/protocol/messages.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::hex;

struct FailureCase {
  const char* title;
  const char* payload_hex;
  RequestError expected;
};

class DecodeRequestFailure : public ::testing::TestWithParam<FailureCase> {};

TEST_P(DecodeRequestFailure, AnswersTheD2Reason) {
  const auto& c = GetParam();
  const auto decoded = decode_request(hex(c.payload_hex));
  ASSERT_FALSE(decoded.has_value()) << c.title;
  EXPECT_EQ(decoded.error(), c.expected) << c.title;
  EXPECT_EQ(failure_reply(decoded.error()), (ServiceFailure{c.expected.request_code, c.expected.reason}));
}

constexpr auto kWrongLength = FailureReason::wrong_length;
constexpr auto kUnknown = FailureReason::unknown_service;
constexpr auto kRange = FailureReason::out_of_range;

INSTANTIATE_TEST_SUITE_P(
    D2, DecodeRequestFailure,
    ::testing::Values(
        // Too short to hold a code: REQUEST_CODE 0 (D2).
        FailureCase{"empty", "", {0x0000, kWrongLength, DecodeError::truncated}},
        FailureCase{"one byte", "01", {0x0000, kWrongLength, DecodeError::truncated}},
        // Unknown codes, responses sent as requests, SERVICE_FAILURE itself.
        FailureCase{"unknown 0x0103", "01 03", {0x0103, kUnknown, DecodeError::unknown_service}},
        FailureCase{"unknown group 0x05", "05 01 00 00", {0x0501, kUnknown, DecodeError::unknown_service}},
        FailureCase{"a response code", "81 02", {0x8102, kUnknown, DecodeError::unknown_service}},
        FailureCase{"SERVICE_FAILURE", "FF 00 01 02 00 01", {0xFF00, kUnknown, DecodeError::unknown_service}},
        // Unpublished layouts answer reason 1 whatever their length (D2).
        FailureCase{"0x0106", "01 06", {0x0106, kUnknown, DecodeError::unpublished_layout}},
        FailureCase{"COM_ATTACH", "06 01 00 01", {0x0601, kUnknown, DecodeError::unpublished_layout}},
        FailureCase{"DIR", "07 01", {0x0701, kUnknown, DecodeError::unpublished_layout}},
        FailureCase{"MONITOR_PROFILE_LOG", "08 02 00", {0x0802, kUnknown, DecodeError::unpublished_layout}},
        // Wrong lengths: odd, missing or surplus WORDs.
        FailureCase{"odd length", "01 01 00", {0x0101, kWrongLength, DecodeError::bad_length}},
        FailureCase{"GET_IDENTIFICATION no item", "01 01", {0x0101, kWrongLength, DecodeError::bad_length}},
        FailureCase{"GET_IDENTIFICATION two words", "01 01 00 01 00 00", {0x0101, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_SIGNAL bare", "01 05", {0x0105, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_TIME_REL surplus", "02 04 00 01 00 00", {0x0204, kWrongLength, DecodeError::bad_length}},
        FailureCase{"DO_RESET bare (S4)", "04 01", {0x0401, kWrongLength, DecodeError::bad_length}},
        FailureCase{"TRANS_ROTATE bare", "04 03", {0x0403, kWrongLength, DecodeError::bad_length}},
        FailureCase{"GET_PROFILE one word", "03 01 00 00", {0x0301, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_FUNCTION three words", "02 0A 00 00 00 03 10 E0", {0x020A, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_FILTER one word", "02 09 00 01", {0x0209, kWrongLength, DecodeError::bad_length}},
        // Parameterless requests: one trailing 0x0000 WORD only (D2).
        FailureCase{"GET_STATUS + 0x0001", "01 02 00 01", {0x0102, kWrongLength, DecodeError::bad_length}},
        FailureCase{"TRANS_IDLE + two zero WORDs", "04 02 00 00 00 00", {0x0402, kWrongLength, DecodeError::bad_length}},
        FailureCase{"CANCEL_PROFILE + one byte", "03 02 00", {0x0302, kWrongLength, DecodeError::bad_length}},
        FailureCase{"TRANS_MEASURE + 0xFFFF", "04 04 FF FF", {0x0404, kWrongLength, DecodeError::bad_length}},
        // SET_CONFIG: key missing, layout length, S2's pad must be zero and only on global.
        FailureCase{"SET_CONFIG no key", "02 01", {0x0201, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_CONFIG global short", "02 01 00 10 00 01 00 0A", {0x0201, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_CONFIG global non-zero pad", "02 01 00 10 00 01 00 0A 00 08 00 01",
                    {0x0201, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_CONFIG global two pads", "02 01 00 10 00 01 00 0A 00 08 00 00 00 00",
                    {0x0201, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_CONFIG RS-232 padded", "02 01 00 01 00 06 00 00 00 01 00 08 00 00",
                    {0x0201, kWrongLength, DecodeError::bad_length}},
        FailureCase{"SET_CONFIG CAN four words", "02 01 00 02 00 04 06 C0 06 C1 00 00",
                    {0x0201, kWrongLength, DecodeError::bad_length}},
        // Closed value sets (syntax, not state): reason 4.
        FailureCase{"SET_CONFIG ARCNET key", "02 01 00 04 00 00", {0x0201, kRange, DecodeError::unknown_config_key}},
        FailureCase{"GET_CONFIG reserved key", "02 02 00 03", {0x0202, kRange, DecodeError::unknown_config_key}},
        FailureCase{"GET_IDENTIFICATION item 5", "01 01 00 05", {0x0101, kRange, DecodeError::out_of_range}},
        FailureCase{"GET_FUNCTION sector 8", "02 0B 00 08", {0x020B, kRange, DecodeError::out_of_range}},
        FailureCase{"SET_FILTER item 2", "02 09 00 02 00 01", {0x0209, kRange, DecodeError::out_of_range}},
        FailureCase{"SET_FILTER value 2", "02 09 00 01 00 02", {0x0209, kRange, DecodeError::out_of_range}},
        FailureCase{"DO_RESET level 3", "04 01 00 03", {0x0401, kRange, DecodeError::out_of_range}}));

struct AcceptCase {
  const char* title;
  const char* payload_hex;
  Request expected;
};

class DecodeRequestAccept : public ::testing::TestWithParam<AcceptCase> {};

TEST_P(DecodeRequestAccept, DecodesAndReencodesExactly) {
  const auto& c = GetParam();
  const Bytes payload = hex(c.payload_hex);
  const auto decoded = decode_request(payload);
  ASSERT_TRUE(decoded.has_value()) << c.title << ": " << describe(decoded.error().detail);
  EXPECT_EQ(*decoded, c.expected) << c.title;
  EXPECT_EQ(encode_request(*decoded), payload) << c.title;
}

INSTANTIATE_TEST_SUITE_P(
    D2, DecodeRequestAccept,
    ::testing::Values(
        AcceptCase{"GET_STATUS + 0x0000", "01 02 00 00", GetStatus{true}},
        AcceptCase{"GET_SIGNAL + 0x0000", "01 04 00 00", GetSignal{true}},
        AcceptCase{"GET_SYNC_CLOCK + 0x0000", "02 05 00 00", GetSyncClock{true}},
        AcceptCase{"CANCEL_PROFILE + 0x0000 (S2)", "03 02 00 00", CancelProfile{true}},
        AcceptCase{"TRANS_IDLE + 0x0000 (S2)", "04 02 00 00", TransIdle{true}},
        AcceptCase{"TRANS_MEASURE + 0x0000 (S2)", "04 04 00 00", TransMeasure{true}},
        AcceptCase{"SET_CONFIG global + 0x0000 (S2)", "02 01 00 10 00 10 00 0A 00 08 00 00",
                   SetConfig{GlobalConfig{0x10, 10, 8, true}}},
        AcceptCase{"SET_CONFIG CAN (D1)", "02 01 00 02 00 04 06 C0 06 C1 00 08 00 05",
                   SetConfig{CanConfig{4, 0x6C0, 0x6C1, 8, 5}}},
        AcceptCase{"SET_CONFIG interlace (S4)", "02 01 00 11 00 03", SetConfig{InterlaceConfig{3}}},
        AcceptCase{"SET_CONFIG Ethernet", "02 01 00 05 00 0A 00 00 00 00 00 01 00 FF 00 00 00 00 00 00 00 0A 00 00 00 00 00 FE 00 07 C0 00",
                   SetConfig{EthernetConfig{{10, 0, 0, 1}, {255, 0, 0, 0}, {10, 0, 0, 254}, 7, 0xC000}}},
        // Raw values: semantic checks belong to the emulator.
        AcceptCase{"TRANS_ROTATE 25 Hz kept raw", "04 03 00 19", TransRotate{25}},
        AcceptCase{"SET_FUNCTION sector 9 kept raw (in-band FF FF)", "02 0A 00 09 00 03 10 E0 00 00",
                   SetFunction{9, 3, 0x10E0, 0}},
        AcceptCase{"GET_PROFILE with bit 15", "03 01 00 05 80 01", GetProfile{5, 0x8001}},
        AcceptCase{"SET_TIME_REL -32768", "02 04 80 00", SetTimeRel{-32768}},
        AcceptCase{"DO_RESET APD level", "04 01 00 10", DoReset{0x10}}));

TEST(RequestService, EveryAlternative_HasItsOwnCode) {
  EXPECT_EQ(service_of(Request{GetIdentification{}}), Service::get_identification);
  EXPECT_EQ(service_of(Request{TransMeasure{}}), Service::trans_measure);
  EXPECT_EQ(service_of(Request{SetConfig{GlobalConfig{}}}), Service::set_config);
}

}  // namespace
}  // namespace ldoem::protocol
