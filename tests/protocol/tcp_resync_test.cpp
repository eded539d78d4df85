// The driver's TCP resynchronisation (TcpResync::rescan_dropped, abandon_frame): a frame cut
// short, a corrupted checksum or garbage between frames costs only the frame it hits, whatever
// the chunking (D11 truncate/corrupt/garbage faults seen from the host).
#include <vector>

#include "ldoem/protocol/tcp_framing.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::concat;
using test::hex;
using test::kClockReply;
using test::kIdleReply;
using test::kStatusReply;
using test::telegrams_of;

const Bytes kProfileLike = hex("83 01 00 00 00 05 01 02 03 04 05 06 07 08");

// A frame whose header promises `claimed` payload bytes but only `payload` follows: the bytes of
// the next frames fill the promise (a frame truncated on the wire).
Bytes cut_frame(const Bytes& payload, std::uint32_t claimed) {
  Bytes frame = {0x02, 0x55, 0x53, 0x50, static_cast<std::uint8_t>(claimed >> 24),
                 static_cast<std::uint8_t>(claimed >> 16), static_cast<std::uint8_t>(claimed >> 8),
                 static_cast<std::uint8_t>(claimed)};
  frame.insert(frame.end(), payload.begin(), payload.end());
  return frame;
}

Bytes corrupted_frame(const Bytes& payload) {
  Bytes frame = encode_tcp_frame(payload);
  frame.back() ^= 0x5A;  // D11 corrupt_checksum: the XOR byte is wrong
  return frame;
}

// good, cut (claims 20 bytes, has 3), good, good, garbage, corrupted, good.
Bytes faulty_tcp_stream() {
  return concat({encode_tcp_frame(kStatusReply), cut_frame(hex("81 02 00"), 20), encode_tcp_frame(kIdleReply),
                 encode_tcp_frame(kProfileLike), hex("FF 02 55 00 13 37 02"), corrupted_frame(kClockReply),
                 encode_tcp_frame(kClockReply)});
}

const std::vector<Bytes> kTcpSurvivors{kStatusReply, kIdleReply, kProfileLike, kClockReply};

TEST(TcpResync, RescanDropped_WholeStream_LosesOnlyTheBrokenFrames) {
  TcpDeframer deframer(kMaxTelegramPayload, TcpResync::rescan_dropped);
  const auto events = deframer.feed(faulty_tcp_stream());
  EXPECT_EQ(telegrams_of(events), kTcpSurvivors);
  EXPECT_EQ(deframer.dropped_frames(), 2u);  // the cut frame (its checksum byte is wrong) and the corrupted one
  EXPECT_FALSE(deframer.in_frame());
}

TEST(TcpResync, AfterError_TheCutFrameSwallowsTheNextOne) {
  // The emulator's mode, for contrast: the reply after the cut frame is lost with it.
  TcpDeframer deframer;
  const auto payloads = telegrams_of(deframer.feed(faulty_tcp_stream()));
  EXPECT_LT(payloads.size(), kTcpSurvivors.size());
}

TEST(TcpResync, RescanDropped_SplitAtEveryOffset_SameTelegrams) {
  const Bytes stream = faulty_tcp_stream();
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    TcpDeframer deframer(kMaxTelegramPayload, TcpResync::rescan_dropped);
    auto events = deframer.feed(ByteView(stream.data(), split));
    auto rest = deframer.feed(ByteView(stream.data() + split, stream.size() - split));
    events.insert(events.end(), rest.begin(), rest.end());
    EXPECT_EQ(telegrams_of(events), kTcpSurvivors) << "split at " << split;
  }
}

TEST(TcpResync, RescanDropped_ByteByByte_SameTelegrams) {
  const Bytes stream = faulty_tcp_stream();
  TcpDeframer deframer(kMaxTelegramPayload, TcpResync::rescan_dropped);
  std::vector<DeframerEvent> events;
  for (const auto byte : stream) {
    auto some = deframer.feed(ByteView(&byte, 1));
    events.insert(events.end(), some.begin(), some.end());
  }
  EXPECT_EQ(telegrams_of(events), kTcpSurvivors);
}

TEST(TcpResync, AbandonFrame_RecoversWhatACutFrameWasHoldingAtEverySplit) {
  // The cut frame promises more than ever comes: only giving it up (after a gap) frees the reply.
  const Bytes stream = concat({cut_frame(hex("81 02"), 500), encode_tcp_frame(kIdleReply)});
  for (std::size_t split = 0; split <= stream.size(); ++split) {
    TcpDeframer deframer(kMaxTelegramPayload, TcpResync::rescan_dropped);
    auto events = deframer.feed(ByteView(stream.data(), split));
    auto rest = deframer.feed(ByteView(stream.data() + split, stream.size() - split));
    events.insert(events.end(), rest.begin(), rest.end());
    EXPECT_TRUE(telegrams_of(events).empty()) << split;
    ASSERT_TRUE(deframer.in_frame()) << split;
    const auto abandoned = deframer.abandon_frame();
    EXPECT_EQ(telegrams_of(abandoned), std::vector<Bytes>{kIdleReply}) << split;
    ASSERT_FALSE(abandoned.empty());
    EXPECT_EQ(abandoned.front(), DeframerEvent(FramingError{DecodeError::truncated, 0x8102})) << split;
    EXPECT_FALSE(deframer.in_frame()) << split;
    EXPECT_EQ(telegrams_of(deframer.feed(encode_tcp_frame(kStatusReply))), std::vector<Bytes>{kStatusReply});
  }
}

TEST(TcpResync, AbandonFrame_WithNoFrameInProgress_GivesNothing) {
  TcpDeframer deframer(kMaxTelegramPayload, TcpResync::rescan_dropped);
  EXPECT_TRUE(deframer.abandon_frame().empty());
  (void)deframer.feed(hex("02 55"));  // a partial magic is garbage once given up
  EXPECT_TRUE(deframer.in_frame());
  EXPECT_TRUE(deframer.abandon_frame().empty());
  EXPECT_FALSE(deframer.in_frame());
  EXPECT_EQ(deframer.dropped_frames(), 0u);
}

TEST(TcpResync, OversizedLength_RescansTheFollowingBytes) {
  // A length above the maximum (a corrupted header) must not hide the frame right after it.
  const Bytes stream = concat({hex("02 55 53 50 7F FF FF FF"), encode_tcp_frame(kStatusReply)});
  TcpDeframer deframer(kMaxTelegramPayload, TcpResync::rescan_dropped);
  EXPECT_EQ(telegrams_of(deframer.feed(stream)), std::vector<Bytes>{kStatusReply});
  EXPECT_EQ(deframer.dropped_frames(), 1u);
}

}  // namespace
}  // namespace ldoem::protocol
