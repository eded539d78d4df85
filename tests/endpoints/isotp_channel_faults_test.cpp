// D11 wire faults on the ISO-TP channel, frame by frame: garbage as stray consecutive frames
// before a message, and the first consecutive frame dropped, repeated or mis-numbered. (The
// daemon's CAN endpoint on vcan: tests/wire_faults/can_wire_faults_test.cpp, label vcan.)
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

// A 20-byte message: FF, then after the host's FC two CFs. Returns every frame that went out.
std::vector<CanFrame> send_twenty_bytes(TelegramFaults faults) {
  IsoTpChannel channel{IsoTpChannelConfig{}};
  auto out = channel.send(0s, counting_bytes(20), std::move(faults));
  std::vector<CanFrame> frames = out.frames;
  out = channel.on_frame(1ms, frame(0x6C0, {0x30, 0x00, 0x00}));
  frames.insert(frames.end(), out.frames.begin(), out.frames.end());
  EXPECT_FALSE(channel.busy());
  return frames;
}

const CanFrame kFirst = frame(0x6C1, {0x10, 0x14, 1, 2, 3, 4, 5, 6});
const CanFrame kCf1 = frame(0x6C1, {0x21, 7, 8, 9, 10, 11, 12, 13});
const CanFrame kCf2 = frame(0x6C1, {0x22, 14, 15, 16, 17, 18, 19, 20});

TEST(IsoTpChannelFaults, NoFault_IsTheUsualMessage) {
  EXPECT_EQ(send_twenty_bytes({}), (std::vector<CanFrame>{kFirst, kCf1, kCf2}));
}

TEST(IsoTpChannelFaults, DropFirstConsecutiveFrame_SendsFirstFrameThenSequenceTwo) {
  TelegramFaults faults;
  faults.first_consecutive_frame = ConsecutiveFrameFault::drop;
  EXPECT_EQ(send_twenty_bytes(faults), (std::vector<CanFrame>{kFirst, kCf2}));
}

TEST(IsoTpChannelFaults, RepeatFirstConsecutiveFrame_SendsItTwice) {
  TelegramFaults faults;
  faults.first_consecutive_frame = ConsecutiveFrameFault::repeat;
  EXPECT_EQ(send_twenty_bytes(faults), (std::vector<CanFrame>{kFirst, kCf1, kCf1, kCf2}));
}

TEST(IsoTpChannelFaults, BadSequenceNumber_NumbersTheFirstConsecutiveFrameTwo) {
  TelegramFaults faults;
  faults.first_consecutive_frame = ConsecutiveFrameFault::bad_sequence;
  EXPECT_EQ(send_twenty_bytes(faults),
            (std::vector<CanFrame>{kFirst, frame(0x6C1, {0x22, 7, 8, 9, 10, 11, 12, 13}), kCf2}));
}

TEST(IsoTpChannelFaults, Garbage_GoesOutAsStrayConsecutiveFramesBeforeTheMessage) {
  TelegramFaults faults;
  faults.garbage_before = Bytes{0x48, 0xBD, 0x68, 0x1C, 0xEE, 0x96, 0x7F, 0xD7, 0x10, 0x35};
  EXPECT_EQ(send_twenty_bytes(faults),
            (std::vector<CanFrame>{frame(0x6C1, {0x28, 0xBD, 0x68, 0x1C, 0xEE, 0x96, 0x7F, 0xD7}),
                                   frame(0x6C1, {0x20, 0x35}), kFirst, kCf1, kCf2}));
}

TEST(IsoTpChannelFaults, GarbageWaitsForTheMessageBeforeIt_NeverSplitsOne) {
  IsoTpChannel channel{IsoTpChannelConfig{}};
  auto out = channel.send(0s, counting_bytes(20));
  ASSERT_EQ(out.frames, (std::vector<CanFrame>{kFirst}));
  TelegramFaults faults;
  faults.garbage_before = Bytes{0x01};
  out = channel.send(0s, Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x01}, faults);
  EXPECT_TRUE(out.frames.empty());  // queued behind the message in flight
  out = channel.on_frame(1ms, frame(0x6C0, {0x30, 0x00, 0x00}));
  EXPECT_EQ(out.frames, (std::vector<CanFrame>{kCf1, kCf2, frame(0x6C1, {0x21}),
                                               frame(0x6C1, {0x06, 0x81, 0x02, 0x00, 0x00, 0x00, 0x01})}));
}

TEST(IsoTpChannelFaults, SingleFrameMessage_KeepsAConsecutiveFrameFaultUnused) {
  IsoTpChannel channel{IsoTpChannelConfig{}};
  TelegramFaults faults;
  faults.first_consecutive_frame = ConsecutiveFrameFault::drop;
  const auto out = channel.send(0s, Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x01}, faults);
  EXPECT_EQ(out.frames, (std::vector<CanFrame>{frame(0x6C1, {0x06, 0x81, 0x02, 0x00, 0x00, 0x00, 0x01})}));
}

}  // namespace
}  // namespace ldoem::endpoints
