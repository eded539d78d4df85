// Every D2 answer to an invalid request that the state table does not already cover.
#include <gtest/gtest.h>

#include "control_test_support.hpp"

namespace ldoem::control::test {
namespace {

struct ReplyFailureCase {
  const char* request;  // text form; raw hex WORDs where the text grammar cannot express it
  const char* reply;
};

void PrintTo(const ReplyFailureCase& c, std::ostream* os) { *os << c.request; }

class InvalidRequest : public ::testing::TestWithParam<ReplyFailureCase> {};

TEST_P(InvalidRequest, IsAnsweredAsD2Decides) {
  Bench bench;
  EXPECT_EQ(bench.reply_text(kTcp1, GetParam().request), GetParam().reply);
  EXPECT_EQ(bench.unit.state(), power_up_state(SimTime{}, factory_config())) << bench.unit.dump(bench.now);
}

INSTANTIATE_TEST_SUITE_P(
    D2, InvalidRequest,
    ::testing::Values(
        // 0x0001 unknown service (and a response code sent to the LD).
        ReplyFailureCase{"0500 0001", "SERVICE_FAILURE 0500 0001"}, ReplyFailureCase{"0103", "SERVICE_FAILURE 0103 0001"},
        ReplyFailureCase{"GET_STATUS reply 0000 0001", "SERVICE_FAILURE 8102 0001"},
        ReplyFailureCase{"SERVICE_FAILURE", "SERVICE_FAILURE ff00 0001"},
        ReplyFailureCase{"SAVE 0001", "SERVICE_FAILURE 0702 0001"},
        // 0x0002 wrong length: missing or surplus WORDs; only one trailing 0x0000 is accepted.
        ReplyFailureCase{"GET_STATUS 0000 0000", "SERVICE_FAILURE 0102 0002"},
        ReplyFailureCase{"GET_STATUS 0001", "SERVICE_FAILURE 0102 0002"},
        ReplyFailureCase{"TRANS_ROTATE", "SERVICE_FAILURE 0403 0002"},
        ReplyFailureCase{"GET_PROFILE 0000", "SERVICE_FAILURE 0301 0002"},
        ReplyFailureCase{"SET_FUNCTION 0000 0003 0870", "SERVICE_FAILURE 020a 0002"},
        ReplyFailureCase{"DO_RESET 0002 0000", "SERVICE_FAILURE 0401 0002"},
        ReplyFailureCase{"0102 00", "SERVICE_FAILURE 0102 0002"},
        ReplyFailureCase{"01", "SERVICE_FAILURE 0000 0002"},  // too short for a code: request code 0
        // 0x0004 parameter out of range.
        ReplyFailureCase{"GET_IDENTIFICATION 0005", "SERVICE_FAILURE 0101 0004"},
        ReplyFailureCase{"GET_IDENTIFICATION 0023", "SERVICE_FAILURE 0101 0004"},
        ReplyFailureCase{"GET_FUNCTION 0008", "SERVICE_FAILURE 020b 0004"},
        ReplyFailureCase{"GET_CONFIG 0003", "SERVICE_FAILURE 0202 0004"},
        ReplyFailureCase{"SET_FILTER 0002 0001", "SERVICE_FAILURE 0209 0004"},
        ReplyFailureCase{"SET_FILTER 0001 0002", "SERVICE_FAILURE 0209 0004"},
        ReplyFailureCase{"TRANS_ROTATE 0003", "SERVICE_FAILURE 0403 0004"},
        ReplyFailureCase{"DO_RESET 0004", "SERVICE_FAILURE 0401 0004"}));

TEST(FramingError, IsAnsweredWithReasonFiveAndTheCodeTheFrameCarried) {
  Bench bench;
  auto out = bench.unit.on_framing_error(bench.now, kTcp1, protocol::FramingError{protocol::DecodeError::bad_checksum, 0x0102});
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(protocol::format_telegram(out.telegrams[0].payload), "SERVICE_FAILURE 0102 0005");
  EXPECT_EQ(out.telegrams[0].to, kTcp1);
  out = bench.unit.on_framing_error(bench.now, kSerial1, protocol::FramingError{protocol::DecodeError::bad_crc, 0});
  EXPECT_EQ(protocol::format_telegram(out.telegrams.at(0).payload), "SERVICE_FAILURE 0000 0005");
  out = bench.unit.on_framing_error(bench.now, kSerial1, protocol::FramingError{protocol::DecodeError::bad_hex, 0});
  EXPECT_EQ(protocol::format_telegram(out.telegrams.at(0).payload), "SERVICE_FAILURE 0000 0005");
  // A serial length WORD that does not match the telegram is a wrong length (protocol's mapping).
  out = bench.unit.on_framing_error(bench.now, kSerial1, protocol::FramingError{protocol::DecodeError::bad_length, 0x0401});
  EXPECT_EQ(protocol::format_telegram(out.telegrams.at(0).payload), "SERVICE_FAILURE 0401 0002");
  EXPECT_EQ(bench.unit.diagnostics().service_failures_sent, 4u);
}

TEST(FramingError, DuringAStream_ChangesNothing) {
  Bench bench;
  bench.enter_measure();
  bench.request(kTcp1, "GET_PROFILE 0000 39ff");
  const DeviceState before = bench.unit.state();
  bench.unit.on_framing_error(bench.now, kTcp1, protocol::FramingError{protocol::DecodeError::bad_header, 0});
  EXPECT_EQ(bench.unit.state(), before);
}

TEST(StaleTimer, IsIgnored) {
  Bench bench;
  const auto out = bench.unit.on_timer(bench.now, TimerId{999}, bench.transport);
  EXPECT_EQ(out, Actions{});
}

}  // namespace
}  // namespace ldoem::control::test
