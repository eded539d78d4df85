// Text form of a telegram (text.hpp): the header's examples, errors, and the inverse property.
#include <random>

#include "ldoem/protocol/text.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::hex;

struct TextExample {
  const char* text;
  const char* payload_hex;
};

// The examples of text.hpp, in the same order.
class TextHeaderExamples : public ::testing::TestWithParam<TextExample> {};

TEST_P(TextHeaderExamples, FormatAndParse_AreInverse) {
  const Bytes payload = hex(GetParam().payload_hex);
  EXPECT_EQ(format_telegram(payload), GetParam().text);
  const auto parsed = parse_telegram(GetParam().text);
  ASSERT_TRUE(parsed.has_value()) << GetParam().text;
  EXPECT_EQ(*parsed, payload);
}

INSTANTIATE_TEST_SUITE_P(Header, TextHeaderExamples,
                         ::testing::Values(TextExample{"GET_PROFILE 0000 39ff", "03 01 00 00 39 ff"},
                                           TextExample{"GET_STATUS", "01 02"},
                                           TextExample{"GET_STATUS reply 0000 0001", "81 02 00 00 00 01"},
                                           TextExample{"SERVICE_FAILURE 0501 0001", "ff 00 05 01 00 01"},
                                           TextExample{"0500 0001", "05 00 00 01"},
                                           TextExample{"GET_IDENTIFICATION reply 4c44 2d", "81 01 4c 44 2d"},
                                           TextExample{"", ""}));

TEST(ParseTelegram, UppercaseHex_IsAccepted) {
  const auto parsed = parse_telegram("GET_PROFILE 0000 39FF");
  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(*parsed, hex("03 01 00 00 39 ff"));
}

TEST(ParseTelegram, LoneByte_IsOneBytePayload) {
  const auto parsed = parse_telegram("4c");
  ASSERT_TRUE(parsed.has_value());
  EXPECT_EQ(*parsed, hex("4c"));
}

class ParseTelegramFailure : public ::testing::TestWithParam<const char*> {};

TEST_P(ParseTelegramFailure, IsBadText) {
  const auto parsed = parse_telegram(GetParam());
  ASSERT_FALSE(parsed.has_value()) << GetParam();
  EXPECT_EQ(parsed.error(), DecodeError::bad_text);
}

INSTANTIATE_TEST_SUITE_P(Grammar, ParseTelegramFailure,
                         ::testing::Values("get_status", "GET_STATUS  0000", " GET_STATUS", "GET_STATUS ",
                                           "GET_STATUS 000", "GET_STATUS 00000", "GET_STATUS 2d 0000",
                                           "SERVICE_FAILURE reply", "NOT_A_SERVICE", "GET_STATUS zzzz",
                                           "reply", "12345"));

TEST(TextForm, RandomPayloads_RoundTrip) {
  std::mt19937 rng(1234);
  for (int trial = 0; trial < 2000; ++trial) {
    Bytes payload(std::uniform_int_distribution<std::size_t>(0, 24)(rng));
    for (auto& byte : payload) byte = static_cast<std::uint8_t>(rng());
    if (trial % 2 == 0 && payload.size() >= 2) payload[0] &= 0x84;  // often a known group
    const auto text = format_telegram(payload);
    const auto parsed = parse_telegram(text);
    ASSERT_TRUE(parsed.has_value()) << text;
    EXPECT_EQ(*parsed, payload) << text;
  }
}

}  // namespace
}  // namespace ldoem::protocol
