// The CAN endpoint's ISO-TP glue (D1, D10): routing by identifier, our flow control, the host's
// flow control pacing our sender, one message per telegram, a bounded queue behind it.
#include <gtest/gtest.h>

#include "isotp_test_frames.hpp"
#include "ldoem/endpoints/isotp_channel.hpp"

namespace ldoem::endpoints {
namespace {

using namespace std::chrono_literals;
using protocol::Bytes;
using protocol::CanFrame;

using test::counting_bytes;
using test::frame;

IsoTpChannel default_channel() { return IsoTpChannel(IsoTpChannelConfig{}); }

TEST(IsoTpChannel, SingleFrameRequest_YieldsTelegram) {
  IsoTpChannel channel = default_channel();
  const auto out = channel.on_frame(0s, frame(0x6C0, {0x02, 0x01, 0x02}));
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0], (Bytes{0x01, 0x02}));
  EXPECT_TRUE(out.frames.empty());
}

TEST(IsoTpChannel, FrameOnAnotherId_IsNotOurs) {
  IsoTpChannel channel = default_channel();
  EXPECT_FALSE(channel.accepts(frame(0x6C2, {0x02, 0x01, 0x02})));
  EXPECT_TRUE(channel.on_frame(0s, frame(0x6C2, {0x02, 0x01, 0x02})).telegrams.empty());
}

TEST(IsoTpChannel, ShortReply_IsOneUnpaddedSingleFrameOnResponseId) {
  IsoTpChannel channel = default_channel();
  const auto out = channel.send(0s, Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x01});
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x06, 0x81, 0x02, 0x00, 0x00, 0x00, 0x01}));
  EXPECT_FALSE(channel.busy());
}

TEST(IsoTpChannel, LongReply_WaitsForHostFlowControlThenSendsAll) {
  IsoTpChannel channel = default_channel();
  const Bytes message = counting_bytes(20);
  auto out = channel.send(0s, message);
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x10, 0x14, 1, 2, 3, 4, 5, 6}));
  EXPECT_TRUE(channel.busy());  // D10: a profile due now would be skipped
  out = channel.on_frame(1ms, frame(0x6C0, {0x30, 0x00, 0x00}));
  ASSERT_EQ(out.frames.size(), 2u);
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x21, 7, 8, 9, 10, 11, 12, 13}));
  EXPECT_EQ(out.frames[1], frame(0x6C1, {0x22, 14, 15, 16, 17, 18, 19, 20}));
  EXPECT_FALSE(channel.busy());
  EXPECT_EQ(channel.counters().telegrams_sent, 1u);
}

// Issue 11: a host answering our first frame with FC WAIT forever no longer holds the channel:
// after N_WFTmax WAITs the message is a send failure and the next telegram goes out.
TEST(IsoTpChannel, HostWaitingForever_EndsTheMessageAfterNWftMax) {
  IsoTpChannel channel = default_channel();
  (void)channel.send(0s, counting_bytes(20));
  (void)channel.send(0s, Bytes{0x01, 0x02});
  IsoTpChannelOutput out;
  for (int wait = 1; wait <= 11; ++wait) out = channel.on_frame(std::chrono::milliseconds(500 * wait), frame(0x6C0, {0x31, 0x00, 0x00}));
  EXPECT_EQ(channel.counters().send_failures, 1u);
  ASSERT_EQ(out.frames.size(), 1u);  // the queued single-frame telegram, at once
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x02, 0x01, 0x02}));
}

TEST(IsoTpChannel, HostBlockSizeAndStMin_PaceOurConsecutiveFrames) {
  IsoTpChannel channel = default_channel();
  (void)channel.send(0s, counting_bytes(30));  // FF + 4 CFs
  auto out = channel.on_frame(0s, frame(0x6C0, {0x30, 0x02, 0x0A}));  // BS 2, STmin 10 ms
  ASSERT_EQ(out.frames.size(), 1u);  // the first CF at once, the next after STmin
  EXPECT_EQ(channel.deadline(), std::optional<SimTime>(10ms));
  out = channel.poll(10ms);
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0].data[0], 0x22);
  out = channel.poll(50ms);  // block of 2 done: waits for the next FC
  EXPECT_TRUE(out.frames.empty());
  out = channel.on_frame(60ms, frame(0x6C0, {0x30, 0x00, 0x00}));
  ASSERT_EQ(out.frames.size(), 2u);
  EXPECT_FALSE(channel.busy());
}

TEST(IsoTpChannel, SecondTelegram_WaitsForTheFirstAsItsOwnMessage) {
  IsoTpChannel channel = default_channel();
  (void)channel.send(0s, counting_bytes(10));
  auto out = channel.send(0s, Bytes{0x81, 0x02});
  EXPECT_TRUE(out.frames.empty());  // never inside the first message (D10)
  out = channel.on_frame(1ms, frame(0x6C0, {0x30, 0x00, 0x00}));
  ASSERT_EQ(out.frames.size(), 2u);
  EXPECT_EQ(out.frames[0].data[0], 0x21);
  EXPECT_EQ(out.frames[1], frame(0x6C1, {0x02, 0x81, 0x02}));
}

TEST(IsoTpChannel, HostNeverSendsFlowControl_MessageTimesOutAndNextStarts) {
  IsoTpChannel channel = default_channel();
  (void)channel.send(0s, counting_bytes(10));
  (void)channel.send(0s, Bytes{0x81, 0x02});
  EXPECT_EQ(channel.deadline(), std::optional<SimTime>(1s));  // D1: N_Bs
  const auto out = channel.poll(1s);
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x02, 0x81, 0x02}));
  EXPECT_EQ(channel.counters().send_failures, 1u);
}

TEST(IsoTpChannel, LongRequest_GetsOurFlowControlAndIsReassembled) {
  IsoTpChannel channel = default_channel();
  auto out = channel.on_frame(0s, frame(0x6C0, {0x10, 0x0A, 0x02, 0x0A, 0x00, 0x00, 0x00, 0x03}));
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x30, 0x00, 0x00}));  // D1: BS 0, STmin 0, unpadded
  out = channel.on_frame(1ms, frame(0x6C0, {0x21, 0x10, 0xE0, 0x00, 0x00}));
  ASSERT_EQ(out.telegrams.size(), 1u);
  EXPECT_EQ(out.telegrams[0], (Bytes{0x02, 0x0A, 0x00, 0x00, 0x00, 0x03, 0x10, 0xE0, 0x00, 0x00}));
}

TEST(IsoTpChannel, BrokenSequence_DropsTheTelegramAndCountsIt) {
  IsoTpChannel channel = default_channel();
  (void)channel.on_frame(0s, frame(0x6C0, {0x10, 0x0A, 0x02, 0x0A, 0x00, 0x00, 0x00, 0x03}));
  const auto out = channel.on_frame(1ms, frame(0x6C0, {0x22, 0x10, 0xE0, 0x00, 0x00}));
  EXPECT_TRUE(out.telegrams.empty());
  EXPECT_TRUE(out.frames.empty());  // D1: nothing is sent
  EXPECT_EQ(channel.counters().receive_errors, 1u);
}

TEST(IsoTpChannel, ConfiguredBlockSize_AppearsInOurFlowControl) {
  IsoTpChannelConfig config;
  config.block_size = 4;
  config.st_min = 5ms;
  IsoTpChannel channel(config);
  const auto out = channel.on_frame(0s, frame(0x6C0, {0x10, 0x0A, 0x02, 0x0A, 0x00, 0x00, 0x00, 0x03}));
  ASSERT_EQ(out.frames.size(), 1u);
  EXPECT_EQ(out.frames[0], frame(0x6C1, {0x30, 0x04, 0x05}));
}

TEST(IsoTpChannel, FullQueue_RefusesAndCounts) {
  IsoTpChannelConfig config;
  config.max_queued_telegrams = 1;
  IsoTpChannel channel(config);
  (void)channel.send(0s, counting_bytes(10));  // in flight
  (void)channel.send(0s, Bytes{0x81, 0x02});   // queued
  (void)channel.send(0s, Bytes{0x81, 0x04});   // refused
  EXPECT_EQ(channel.counters().queue_overflows, 1u);
}

}  // namespace
}  // namespace ldoem::endpoints
