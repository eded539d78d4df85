// Serial framing (spec 4.2): CRC, host telegrams, LD reply packages (our choices), both
// streaming decoders run whole, byte by byte and split at every offset.
#include <cstdio>
#include <random>

#include "ldoem/protocol/serial_framing.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::ascii;
using test::concat;
using test::framing_error;
using test::hex;
using test::serial_wire;
using test::telegram;

const Bytes kGetStatusWire = serial_wire("00100003000001026d36");
const Bytes kDoReset2Wire = serial_wire("0010000400000401000283a3");

TEST(SerialCrc, CheckValues) {
  EXPECT_EQ(serial_crc(ascii("123456789")), 0xA69D);
  EXPECT_EQ(serial_crc(hex("00 10 00 03 00 00 01 02")), 0x6D36);
  EXPECT_EQ(serial_crc(hex("00 00")), 0x1D0F);
  EXPECT_EQ(serial_crc({}), 0xFFFF);
}

TEST(EncodeSerialRequest, IntoSpan_LeavesGuardBytesUntouched) {
  std::array<std::uint8_t, 26> buffer;
  buffer.fill(0xEE);
  const auto used = encode_serial_request_into(hex("01 02"), std::span(buffer).subspan(2, 22));
  ASSERT_TRUE(used.has_value());
  EXPECT_EQ(*used, kGetStatusWire.size());
  EXPECT_EQ(Bytes(buffer.begin() + 2, buffer.begin() + 24), kGetStatusWire);
  for (std::size_t i : {0u, 1u, 24u, 25u}) EXPECT_EQ(buffer[i], 0xEE) << i;
  std::array<std::uint8_t, 21> short_buffer;
  short_buffer.fill(0xEE);
  EXPECT_FALSE(encode_serial_request_into(hex("01 02"), short_buffer).has_value());
  for (const auto byte : short_buffer) EXPECT_EQ(byte, 0xEE);
}

TEST(EncodeSerialRequest, OddPayload_IsPaddedWithZero) {
  EXPECT_EQ(encode_serial_request(hex("01 01 00")), encode_serial_request(hex("01 01 00 00")));
}

TEST(SerialDeframer, UppercaseHex_IsAccepted) {
  test::expect_events_every_split([] { return SerialDeframer(); }, serial_wire("00100003000001026D36"),
                                  {telegram(hex("01 02"))});
}

TEST(SerialDeframer, GarbageAndNoise_AreSkipped) {
  const Bytes stream = concat({ascii("xx\x03zz"), kGetStatusWire, ascii("\r\n"), kDoReset2Wire});
  test::expect_events_every_split([] { return SerialDeframer(); }, stream,
                                  {telegram(hex("01 02")), telegram(hex("04 01 00 02"))});
  SerialDeframer deframer;
  (void)deframer.feed(stream);
  EXPECT_EQ(deframer.skipped_bytes(), 7u);
}

struct BadTelegram {
  const char* title;
  Bytes wire;
  FramingError expected;
};

class SerialDeframerFailure : public ::testing::TestWithParam<BadTelegram> {};

TEST_P(SerialDeframerFailure, ReportsThenResyncs) {
  const auto& c = GetParam();
  SCOPED_TRACE(c.title);
  test::expect_events_every_split([] { return SerialDeframer(); }, concat({c.wire, kGetStatusWire}),
                                  {DeframerEvent{c.expected}, telegram(hex("01 02"))});
  SerialDeframer deframer;
  (void)deframer.feed(concat({c.wire, kGetStatusWire}));
  EXPECT_EQ(deframer.dropped_frames(), 1u);
}

INSTANTIATE_TEST_SUITE_P(
    Serial, SerialDeframerFailure,
    ::testing::Values(
        BadTelegram{"bad CRC", serial_wire("00100003000001026d37"), {DecodeError::bad_crc, 0x0102}},
        BadTelegram{"non-hex digit", serial_wire("00100003000001g26d36"), {DecodeError::bad_hex, 0x0000}},
        BadTelegram{"non-hex after the service", serial_wire("001000030000010200x0"), {DecodeError::bad_hex, 0x0102}},
        BadTelegram{"partial WORD", serial_wire("00100003000001026d3"), {DecodeError::bad_hex, 0x0102}},
        BadTelegram{"LLLL mismatch (S2 GET_CONFIG)", serial_wire("001000060000020200015de6"),
                    {DecodeError::bad_length, 0x0202}},
        BadTelegram{"empty", serial_wire(""), {DecodeError::truncated, 0}},
        BadTelegram{"cut by a new STX", Bytes{0x02, '0', '0', '1', '0'}, {DecodeError::truncated, 0}}));

TEST(SerialDeframer, NonZeroPackageId_IsUnexpectedFrame) {
  // WORDs 0010 0003 0001 0102 with a valid CRC.
  Bytes words = hex("00 10 00 03 00 01 01 02");
  const std::uint16_t crc = serial_crc(words);
  char crc_text[5];
  std::snprintf(crc_text, sizeof crc_text, "%04x", crc);
  const Bytes wire = serial_wire(std::string("0010000300010102") + crc_text);
  test::expect_events_every_split([] { return SerialDeframer(); }, wire,
                                  {framing_error(DecodeError::unexpected_frame, 0x0102)});
}

TEST(SerialDeframer, AddressAndCrcOnly_IsTruncated) {
  char crc_text[5];
  std::snprintf(crc_text, sizeof crc_text, "%04x", serial_crc(hex("00 10")));
  test::expect_events_every_split([] { return SerialDeframer(); }, serial_wire(std::string("0010") + crc_text),
                                  {framing_error(DecodeError::truncated)});
}

TEST(SerialDeframer, TooManyWords_IsTooLargeAndBounded) {
  auto make = [] { return SerialDeframer(4); };  // 4 payload bytes at most
  const Bytes ok = encode_serial_request(hex("01 01 00 01"));
  const Bytes too_long = encode_serial_request(hex("02 0A 00 00 00 03"));
  test::expect_events_every_split(make, concat({too_long, ok}),
                                  {framing_error(DecodeError::too_large, 0x020A), telegram(hex("01 01 00 01"))});
}

TEST(SerialReply, ShortReply_IsOnePackageWithCountOne) {
  // Our choices: address 0x1000, W2 0, NNNN 1 (docs/protocol.md).
  const Bytes payload = hex("81 02 00 00 00 01");
  const auto packages = encode_serial_reply_packages(payload);
  ASSERT_EQ(packages.size(), 1u);
  const Bytes words = hex("10 00 00 06 00 00 00 01 81 02 00 00 00 01");
  char crc_text[5];
  std::snprintf(crc_text, sizeof crc_text, "%04x", serial_crc(words));
  EXPECT_EQ(packages[0], serial_wire(std::string("1000000600000001810200000001") + crc_text));
}

TEST(SerialReply, LongReply_SplitsAt126LengthWords) {
  // 123 WORDs fit the first package; 124 per continuation.
  EXPECT_EQ(encode_serial_reply_packages(Bytes(2 * 123, 0x11)).size(), 1u);
  EXPECT_EQ(encode_serial_reply_packages(Bytes(2 * 124, 0x11)).size(), 2u);
  EXPECT_EQ(encode_serial_reply_packages(Bytes(2 * (123 + 124), 0x11)).size(), 2u);
  EXPECT_EQ(encode_serial_reply_packages(Bytes(2 * (123 + 124) + 1, 0x11)).size(), 3u);
  const auto packages = encode_serial_reply_packages(Bytes(2 * 400, 0x22));
  ASSERT_EQ(packages.size(), 4u);
  // Length WORD at hex offset 5..8, W2/QQQQ at 9..12, NNNN at 13..16 (first only).
  auto word_at = [](const Bytes& package, std::size_t word) {
    return std::stoul(std::string(package.begin() + 1 + 4 * word, package.begin() + 5 + 4 * word), nullptr, 16);
  };
  EXPECT_EQ(word_at(packages[0], 1), 126u);
  EXPECT_EQ(word_at(packages[0], 2), 0u);
  EXPECT_EQ(word_at(packages[0], 3), 4u);
  EXPECT_EQ(word_at(packages[1], 1), 126u);
  EXPECT_EQ(word_at(packages[1], 2), 3u);
  EXPECT_EQ(word_at(packages[2], 2), 2u);
  EXPECT_EQ(word_at(packages[3], 2), 1u);
  EXPECT_EQ(word_at(packages[3], 1), 2u + (400 - 123 - 124 - 124));
  for (const auto& package : packages) EXPECT_LE(package.size(), 2u + 4 * 128);
}

TEST(SerialReplyReassembler, LongReply_ReassemblesEverySplit) {
  Bytes payload(2 * 300);
  std::mt19937 rng(7);
  for (auto& byte : payload) byte = static_cast<std::uint8_t>(rng());
  const Bytes stream = concat({encode_serial_reply(payload), encode_serial_reply(hex("84 01 00 02"))});
  test::expect_events_every_split([] { return SerialReplyReassembler(); }, stream,
                                  {telegram(payload), telegram(hex("84 01 00 02"))});
}

TEST(SerialReplyReassembler, OddPayload_ComesBackPadded) {
  SerialReplyReassembler reassembler;
  EXPECT_EQ(reassembler.feed(encode_serial_reply(hex("81 01 4C"))),
            (std::vector<DeframerEvent>{telegram(hex("81 01 4C 00"))}));
}

TEST(SerialReplyReassembler, MaxPayload_Reassembles) {
  const Bytes payload(kMaxTelegramPayload, 0x5A);
  SerialReplyReassembler reassembler;
  EXPECT_EQ(reassembler.feed(encode_serial_reply(payload)), (std::vector<DeframerEvent>{telegram(payload)}));
}

TEST(SerialReplyReassembler, MissingContinuation_IsBadSequence) {
  const auto packages = encode_serial_reply_packages(Bytes(2 * 400, 0x22));
  const Bytes short_reply = encode_serial_reply(hex("84 02 00 00 00 01"));
  const Bytes stream = concat({packages[0], packages[1], packages[3], short_reply});
  test::expect_events_every_split([] { return SerialReplyReassembler(); }, stream,
                                  {framing_error(DecodeError::bad_sequence), telegram(hex("84 02 00 00 00 01"))});
}

TEST(SerialReplyReassembler, NewFirstPackageMidReply_DropsPartial) {
  const auto packages = encode_serial_reply_packages(Bytes(2 * 200, 0x22));
  const Bytes short_reply = encode_serial_reply(hex("84 02 00 00 00 01"));
  test::expect_events_every_split([] { return SerialReplyReassembler(); }, concat({packages[0], short_reply}),
                                  {framing_error(DecodeError::bad_sequence), telegram(hex("84 02 00 00 00 01"))});
}

TEST(SerialReplyReassembler, ContinuationWithoutFirst_IsUnexpected) {
  const auto packages = encode_serial_reply_packages(Bytes(2 * 200, 0x22));
  test::expect_events_every_split([] { return SerialReplyReassembler(); }, packages[1],
                                  {framing_error(DecodeError::unexpected_frame)});
}

TEST(SerialReplyReassembler, BadCrcInContinuation_DropsReply) {
  auto packages = encode_serial_reply_packages(Bytes(2 * 200, 0x22));
  auto& last_crc_digit = packages[1][packages[1].size() - 2];
  last_crc_digit = last_crc_digit == '0' ? '1' : '0';
  SerialReplyReassembler reassembler;
  const auto events = reassembler.feed(concat({packages[0], packages[1]}));
  EXPECT_EQ(events, (std::vector<DeframerEvent>{framing_error(DecodeError::bad_crc)}));
  EXPECT_FALSE(reassembler.in_reply());
  EXPECT_EQ(reassembler.dropped_frames(), 1u);
}

TEST(SerialReplyReassembler, PackageCountAboveMax_IsTooLarge) {
  const Bytes words = hex("10 00 00 04 00 00 00 40 81 02");  // NNNN 64
  char crc_text[5];
  std::snprintf(crc_text, sizeof crc_text, "%04x", serial_crc(words));
  test::expect_events_every_split([] { return SerialReplyReassembler(); },
                                  serial_wire(std::string("10000004000000408102") + crc_text),
                                  {framing_error(DecodeError::too_large)});
}

}  // namespace
}  // namespace ldoem::protocol
