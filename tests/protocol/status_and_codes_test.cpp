// Service names and codes (spec 3.2, 2.2) and the status byte (spec 2.4, D3).
#include "ldoem/protocol/service_codes.hpp"
#include "ldoem/protocol/status.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

TEST(ServiceName, RequestsAndReplies_AreNamed) {
  EXPECT_EQ(service_name(0x0102), "GET_STATUS");
  EXPECT_EQ(service_name(0x8102), "GET_STATUS reply");
  EXPECT_EQ(service_name(0x0301), "GET_PROFILE");
  EXPECT_EQ(service_name(0x8301), "GET_PROFILE reply");
  EXPECT_EQ(service_name(0x0106), "LD_REGISTER_APPLICATION");
  EXPECT_EQ(service_name(0xFF00), "SERVICE_FAILURE");
  EXPECT_EQ(service_name(0x0103), "unknown service");
  EXPECT_EQ(service_name(0x7F00), "unknown service");
}

TEST(ServiceName, EveryKnownCode_RoundTripsThroughItsName) {
  int known = 0;
  for (unsigned code = 0; code <= 0xFFFF; ++code) {
    const auto word = static_cast<std::uint16_t>(code);
    if (!is_known_code(word)) {
      EXPECT_FALSE(service_code_from_name(service_name(word)).has_value());
      continue;
    }
    ++known;
    EXPECT_EQ(service_code_from_name(service_name(word)), word) << service_name(word);
  }
  EXPECT_EQ(known, 30 * 2 + 1);  // 30 requests, their replies, SERVICE_FAILURE
}

TEST(ResponseCode, SetsBit15) {
  EXPECT_EQ(response_code(0x0102), 0x8102);
  EXPECT_EQ(response_code(Service::trans_measure), 0x8404);
  EXPECT_TRUE(is_response(0x8301));
  EXPECT_TRUE(is_response(0xFF00));
  EXPECT_FALSE(is_response(0x0301));
}

TEST(RequestService, UnpublishedLayouts_AreFlagged) {
  EXPECT_TRUE(has_unpublished_layout(Service::ld_register_application));
  EXPECT_TRUE(has_unpublished_layout(Service::com_data));
  EXPECT_TRUE(has_unpublished_layout(Service::file_delete));
  EXPECT_TRUE(has_unpublished_layout(Service::monitor_run));
  EXPECT_FALSE(has_unpublished_layout(Service::get_profile));
  EXPECT_FALSE(request_service(0xFF00).has_value());
  EXPECT_FALSE(request_service(0x8102).has_value());
}

TEST(StatusByte, LowNibbleSensor_HighNibbleMotor) {
  EXPECT_EQ((StatusByte{SensorMode::measure, MotorMode::ok}.to_byte()), 0x03);
  EXPECT_EQ((StatusByte{SensorMode::rotate, MotorMode::spin_too_low}.to_byte()), 0x42);
  EXPECT_EQ((StatusByte{SensorMode::error, MotorMode::fault}.to_byte()), 0xB4);
  EXPECT_EQ(StatusByte::from_byte(0x91), (StatusByte{SensorMode::idle, MotorMode::spin_too_high}));
  EXPECT_TRUE(StatusByte::from_byte(0xB4).is_known());
  EXPECT_FALSE(StatusByte::from_byte(0x05).is_known());
  EXPECT_FALSE(StatusByte::from_byte(0x13).is_known());
}

TEST(StatusByte, EveryByte_RoundTrips) {
  for (unsigned byte = 0; byte < 256; ++byte) {
    EXPECT_EQ(StatusByte::from_byte(static_cast<std::uint8_t>(byte)).to_byte(), byte);
  }
}

TEST(StatusBlock, Default_IsThreeZeroBytesThenStatus) {
  Bytes out;
  append_status_block(out, make_status_block(SensorMode::measure, MotorMode::ok));
  EXPECT_EQ(out, test::hex("00 00 00 03"));  // D3
  EXPECT_EQ(read_status_block(out, 0), make_status_block(SensorMode::measure, MotorMode::ok));
}

TEST(Describe, EveryDecodeError_HasText) {
  for (int i = 0; i <= static_cast<int>(DecodeError::bad_text); ++i) {
    EXPECT_FALSE(describe(static_cast<DecodeError>(i)).empty());
    EXPECT_NE(describe(static_cast<DecodeError>(i)), "unlisted decode error") << i;
  }
}

TEST(FailureReason, WordValues_MatchD2) {
  EXPECT_EQ(static_cast<std::uint16_t>(FailureReason::unknown_service), 1);
  EXPECT_EQ(static_cast<std::uint16_t>(FailureReason::wrong_length), 2);
  EXPECT_EQ(static_cast<std::uint16_t>(FailureReason::wrong_state), 3);
  EXPECT_EQ(static_cast<std::uint16_t>(FailureReason::out_of_range), 4);
  EXPECT_EQ(static_cast<std::uint16_t>(FailureReason::framing), 5);
  EXPECT_EQ(static_cast<std::uint16_t>(FailureReason::flash_not_stored), 6);  // ours, L-flash-1
  EXPECT_EQ(failure_reason_for_framing(DecodeError::bad_crc), FailureReason::framing);
  EXPECT_EQ(failure_reason_for_framing(DecodeError::bad_checksum), FailureReason::framing);
  EXPECT_EQ(failure_reason_for_framing(DecodeError::bad_length), FailureReason::wrong_length);
}

}  // namespace
}  // namespace ldoem::protocol
