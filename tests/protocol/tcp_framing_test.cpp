// TCP framing (spec 4.1): encoder with guard bytes, streaming deframer run whole, byte by byte
// and split at every offset.
#include "ldoem/protocol/tcp_framing.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::concat;
using test::framing_error;
using test::hex;
using test::telegram;

const Bytes kGetStatusFrame = hex("02 55 53 50 00 00 00 02 01 02 03");
const Bytes kTransIdleFrame = hex("02 55 53 50 00 00 00 02 04 02 06");

TEST(EncodeTcpFrame, IntoSpan_LeavesGuardBytesUntouched) {
  const Bytes payload = hex("01 02");
  std::array<std::uint8_t, 16> buffer;
  buffer.fill(0xEE);
  const auto used = encode_tcp_frame_into(payload, std::span(buffer).subspan(2, 12));
  ASSERT_TRUE(used.has_value());
  EXPECT_EQ(*used, kGetStatusFrame.size());
  EXPECT_EQ(Bytes(buffer.begin() + 2, buffer.begin() + 2 + 11), kGetStatusFrame);
  for (std::size_t i : {0u, 1u, 13u, 14u, 15u}) EXPECT_EQ(buffer[i], 0xEE) << i;
}

TEST(EncodeTcpFrame, IntoShortSpan_IsTooLargeAndWritesNothing) {
  std::array<std::uint8_t, 10> buffer;
  buffer.fill(0xEE);
  const auto used = encode_tcp_frame_into(hex("01 02"), buffer);
  ASSERT_FALSE(used.has_value());
  EXPECT_EQ(used.error(), DecodeError::too_large);
  for (const auto byte : buffer) EXPECT_EQ(byte, 0xEE);
}

TEST(EncodeTcpFrame, EmptyPayload_HasZeroLengthAndChecksum) {
  EXPECT_EQ(encode_tcp_frame({}), hex("02 55 53 50 00 00 00 00 00"));
}

TEST(TcpDeframer, TwoFramesBackToBack_YieldBoth) {
  test::expect_events_every_split([] { return TcpDeframer(); }, concat({kGetStatusFrame, kTransIdleFrame}),
                                  {telegram(hex("01 02")), telegram(hex("04 02"))});
}

TEST(TcpDeframer, GarbageBeforeHeader_IsSkippedAndCounted) {
  const Bytes garbage = hex("00 02 55 02 02 55 53 FF 50");
  const Bytes stream = concat({garbage, kGetStatusFrame});
  test::expect_events_every_split([] { return TcpDeframer(); }, stream, {telegram(hex("01 02"))});
  TcpDeframer deframer;
  (void)deframer.feed(stream);
  EXPECT_EQ(deframer.skipped_bytes(), garbage.size());
  EXPECT_EQ(deframer.dropped_frames(), 0u);
}

TEST(TcpDeframer, BadChecksum_YieldsErrorWithCodeThenResyncs) {
  Bytes broken = kGetStatusFrame;
  broken.back() ^= 0xFF;
  test::expect_events_every_split([] { return TcpDeframer(); }, concat({broken, kTransIdleFrame}),
                                  {framing_error(DecodeError::bad_checksum, 0x0102), telegram(hex("04 02"))});
  TcpDeframer deframer;
  (void)deframer.feed(broken);
  EXPECT_EQ(deframer.dropped_frames(), 1u);
}

TEST(TcpDeframer, LengthAboveMax_YieldsTooLargeThenResyncs) {
  const Bytes oversized = hex("02 55 53 50 00 00 16 B9");  // 5817 > 5816
  test::expect_events_every_split([] { return TcpDeframer(); }, concat({oversized, kTransIdleFrame}),
                                  {framing_error(DecodeError::too_large), telegram(hex("04 02"))});
}

TEST(TcpDeframer, LengthAtMax_IsAccepted) {
  const Bytes payload(kMaxTelegramPayload, 0x00);
  TcpDeframer deframer;
  const auto events = deframer.feed(encode_tcp_frame(payload));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0], telegram(payload));
}

TEST(TcpDeframer, ConfiguredMax_IsHonoured) {
  auto make = [] { return TcpDeframer(2); };
  test::expect_events_every_split(make, concat({hex("02 55 53 50 00 00 00 04 01 01 00 00 00"), kGetStatusFrame}),
                                  {framing_error(DecodeError::too_large), telegram(hex("01 02"))});
}

TEST(TcpDeframer, EmptyPayload_IsATelegram) {
  test::expect_events_every_split([] { return TcpDeframer(); }, hex("02 55 53 50 00 00 00 00 00"), {telegram({})});
}

TEST(TcpDeframer, PartialFrame_YieldsNothingYet) {
  TcpDeframer deframer;
  EXPECT_TRUE(deframer.feed(ByteView(kGetStatusFrame).first(10)).empty());
  EXPECT_TRUE(deframer.in_frame());
  EXPECT_EQ(deframer.feed(ByteView(kGetStatusFrame).subspan(10)), (std::vector<DeframerEvent>{telegram(hex("01 02"))}));
  EXPECT_FALSE(deframer.in_frame());
}

TEST(TcpDeframer, ResetDropsPartialFrame) {
  TcpDeframer deframer;
  (void)deframer.feed(ByteView(kGetStatusFrame).first(9));
  deframer.reset();
  EXPECT_EQ(deframer.feed(kTransIdleFrame), (std::vector<DeframerEvent>{telegram(hex("04 02"))}));
}

}  // namespace
}  // namespace ldoem::protocol
