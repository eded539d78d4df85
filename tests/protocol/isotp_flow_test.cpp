// ISO-TP (D1) in time: flow control as the sender sees it (wait, overflow, block size, STmin),
// the receiver's overflow and block size, the N_Cr / N_Bs timeouts, STmin encoding, and random
// sender -> receiver round trips in simulated time. Frame layouts: isotp_test.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <random>
#include <vector>

#include "isotp_test_support.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::protocol {
namespace {

using namespace isotp_test;
using std::chrono::microseconds;
using std::chrono::milliseconds;

// ---------------------------------------------------------------------------------------------
// Flow control as the sender sees it

TEST(IsoTpSender, FlowControlWaitThenContinue_SendsAfterContinue) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.on_flow_control(milliseconds(10), host({0x31, 0x00, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
  // WAIT restarts N_Bs: the deadline is 1000 ms after the WAIT frame, not after the FF.
  EXPECT_EQ(sender.deadline(), milliseconds(1010));
  const IsoTpSendPoll while_waiting = sender.poll(milliseconds(1005));
  EXPECT_TRUE(while_waiting.frames.empty());
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);

  sender.on_flow_control(milliseconds(1006), host({0x30, 0x00, 0x00}));
  const std::vector<CanFrame> frames = sender.poll(milliseconds(1006)).frames;
  EXPECT_EQ(frames.size(), 2u);
  EXPECT_EQ(sender.state(), IsoTpSender::State::done);
}

// Issue 11: N_WFTmax. Each WAIT restarts N_Bs, so a receiver answering WAIT forever held the
// sender forever; now the WAIT after the tenth in a row ends the message, and a CTS in between
// starts the count again.
TEST(IsoTpSender, MoreWaitsInARowThanNWftMax_Fail) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  for (std::uint32_t wait = 1; wait <= kIsoTpDefaultMaxWaitFrames; ++wait) {
    sender.on_flow_control(milliseconds(500 * wait), host({0x31, 0x00, 0x00}));
    ASSERT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control) << "WAIT " << wait;
  }
  sender.on_flow_control(milliseconds(5500), host({0x31, 0x00, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::failed);
  EXPECT_EQ(sender.error(), IsoTpSendError::too_many_waits);
}

TEST(IsoTpSender, WaitsCountOnlyInARow_ACtsStartsAgain) {
  IsoTpSenderConfig config = sender_config();
  config.max_wait_frames = 2;
  IsoTpSender sender(config);
  (void)start_and_poll(sender, {}, counting_bytes(40));
  sender.on_flow_control({}, host({0x31, 0x00, 0x00}));
  sender.on_flow_control({}, host({0x31, 0x00, 0x00}));
  sender.on_flow_control({}, host({0x30, 0x01, 0x00}));  // CTS, block size 1
  (void)sender.poll({});
  sender.on_flow_control({}, host({0x31, 0x00, 0x00}));
  sender.on_flow_control({}, host({0x31, 0x00, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
  sender.on_flow_control({}, host({0x31, 0x00, 0x00}));
  EXPECT_EQ(sender.error(), IsoTpSendError::too_many_waits);
}

TEST(IsoTpSender, FlowControlOverflow_Fails) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.on_flow_control({}, host({0x32, 0x00, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::failed);
  EXPECT_EQ(sender.error(), IsoTpSendError::overflow);
  EXPECT_TRUE(sender.poll(milliseconds(1)).frames.empty());
  EXPECT_FALSE(sender.deadline().has_value());
}

TEST(IsoTpSender, FlowControlReservedStatus_Fails) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.on_flow_control({}, host({0x33, 0x00, 0x00}));
  EXPECT_EQ(sender.error(), IsoTpSendError::invalid_flow_status);
}

TEST(IsoTpSender, FlowControlThreeBytes_BlockSizeAndStMinHonoured) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(6 + 7 * 3));
  sender.on_flow_control({}, host({0x30, 0x02, 0x05}));  // BS 2, STmin 5 ms, 3 bytes
  const IsoTpSendPoll first = sender.poll({});
  ASSERT_EQ(first.frames.size(), 1u);
  EXPECT_EQ(first.frames[0].data[0], 0x21);
  EXPECT_EQ(first.deadline, milliseconds(5));
  EXPECT_TRUE(sender.poll(milliseconds(4)).frames.empty());
  const IsoTpSendPoll second = sender.poll(milliseconds(5));
  ASSERT_EQ(second.frames.size(), 1u);
  EXPECT_EQ(second.frames[0].data[0], 0x22);
  // Block of 2 complete: wait for the next FC, with N_Bs counted from the last CF.
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
  EXPECT_EQ(second.deadline, milliseconds(1005));
  // An FC right away still keeps STmin after the previous CF.
  sender.on_flow_control(milliseconds(6), host({0x30, 0x02, 0x05}));
  EXPECT_EQ(sender.deadline(), milliseconds(10));
  const IsoTpSendPoll third = sender.poll(milliseconds(10));
  ASSERT_EQ(third.frames.size(), 1u);
  EXPECT_EQ(third.frames[0].data[0], 0x23);
  EXPECT_EQ(sender.state(), IsoTpSender::State::done);
}

TEST(IsoTpSender, FlowControlPadded_Accepted) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.on_flow_control({}, host({0x30, 0x00, 0x00, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC}));
  EXPECT_EQ(sender.poll({}).frames.size(), 2u);
}

TEST(IsoTpSender, FlowControlShorterThanThreeBytes_Ignored) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.on_flow_control({}, host({0x30, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
  EXPECT_TRUE(sender.poll({}).frames.empty());
}

TEST(IsoTpSender, FlowControlWhileIdle_Ignored) {
  IsoTpSender sender(sender_config());
  sender.on_flow_control({}, host({0x32, 0x00, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::idle);
  EXPECT_FALSE(sender.error().has_value());
}

TEST(IsoTpSender, StMinMicroseconds_SpacesConsecutiveFrames) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(6 + 7 * 3));
  sender.on_flow_control({}, host({0x30, 0x00, 0xF3}));  // 300 us
  EXPECT_EQ(sender.poll({}).frames.size(), 1u);
  EXPECT_EQ(sender.deadline(), microseconds(300));
  EXPECT_EQ(sender.poll(microseconds(300)).frames.size(), 1u);
  EXPECT_EQ(sender.deadline(), microseconds(600));
}

TEST(IsoTpSender, StartWhileSending_Busy) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  const auto second = sender.start({}, counting_bytes(3));
  ASSERT_FALSE(second.has_value());
  EXPECT_EQ(second.error(), IsoTpSendError::busy);
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
}

TEST(IsoTpSender, ResetWhileWaiting_IdleAndRestartable) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.reset();
  EXPECT_EQ(sender.state(), IsoTpSender::State::idle);
  EXPECT_EQ(start_and_poll(sender, {}, counting_bytes(2)).size(), 1u);
}

TEST(IsoTpReceiver, FirstFrameTooLarge_OverflowFlowControlAndCounted) {
  IsoTpReceiverConfig config = receiver_config();
  config.max_message_bytes = 100;
  IsoTpReceiver receiver(config);
  const IsoTpReceiveResult result =
      receiver.on_frame({}, host({0x10, 0xC8, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));  // 200
  ASSERT_TRUE(result.flow_control.has_value());
  EXPECT_EQ(*result.flow_control, device({0x32, 0x00, 0x00}));
  EXPECT_EQ(result.error, IsoTpReceiveError::too_large);
  EXPECT_EQ(receiver.counters().too_large, 1u);
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
}

TEST(IsoTpRoundTrip, ReceiverTooSmall_SenderFailsWithOverflow) {
  IsoTpSender sender(sender_config());
  IsoTpReceiverConfig config = receiver_config();
  config.max_message_bytes = 5000;
  IsoTpReceiver receiver(config);
  const Transfer transfer = run_transfer(sender, receiver, counting_bytes(5800));
  EXPECT_EQ(transfer.final_state, IsoTpSender::State::failed);
  EXPECT_EQ(sender.error(), IsoTpSendError::overflow);
  EXPECT_EQ(transfer.data_frames.size(), 1u);
  EXPECT_TRUE(transfer.messages.empty());
}

TEST(IsoTpReceiver, OurBlockSize2_FlowControlEveryTwoFrames) {
  IsoTpSender sender(sender_config());
  IsoTpReceiver receiver(receiver_config(2));
  const Transfer transfer = run_transfer(sender, receiver, counting_bytes(6 + 7 * 5));
  ASSERT_EQ(transfer.messages.size(), 1u);
  // FC after the FF, after CF 2 and after CF 4; CF 5 ends the message.
  EXPECT_EQ(transfer.flow_control_frames.size(), 3u);
}

// ---------------------------------------------------------------------------------------------
// Timeouts (D1: N_Cr = N_Bs = 1000 ms)

TEST(IsoTpReceiver, NcrTimeout_DropsPartialTelegram) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  (void)receiver.on_frame(milliseconds(500),
                          host({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
  // N_Cr restarts with each CF.
  EXPECT_EQ(receiver.deadline(), milliseconds(1500));
  EXPECT_TRUE(receiver.on_timer(milliseconds(1499)).nothing());
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::receiving);

  const IsoTpReceiveResult expired = receiver.on_timer(milliseconds(1500));
  EXPECT_EQ(expired.error, IsoTpReceiveError::timeout);
  EXPECT_FALSE(expired.flow_control.has_value());
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
  EXPECT_EQ(receiver.counters().timeout, 1u);
  EXPECT_FALSE(receiver.deadline().has_value());
}

TEST(IsoTpReceiver, ConsecutiveFrameAfterNcr_TimeoutAndFrameIgnored) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  const IsoTpReceiveResult late =
      receiver.on_frame(milliseconds(1000), host({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
  EXPECT_EQ(late.error, IsoTpReceiveError::timeout);
  EXPECT_EQ(receiver.counters().timeout, 1u);
  EXPECT_EQ(receiver.counters().unexpected_frame, 0u);
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
}

TEST(IsoTpSender, NbsTimeout_Fails) {
  IsoTpSender sender(sender_config());
  const base::SimTime start = milliseconds(20);
  (void)start_and_poll(sender, start, counting_bytes(20));
  const IsoTpSendPoll before = sender.poll(start + milliseconds(999));
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
  EXPECT_EQ(before.deadline, start + milliseconds(1000));

  const IsoTpSendPoll expired = sender.poll(start + milliseconds(1000));
  EXPECT_TRUE(expired.frames.empty());
  EXPECT_EQ(sender.state(), IsoTpSender::State::failed);
  EXPECT_EQ(sender.error(), IsoTpSendError::timeout);
  EXPECT_FALSE(expired.deadline.has_value());
}

TEST(IsoTpSender, FlowControlAfterNbs_TimeoutNotContinue) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(20));
  sender.on_flow_control(milliseconds(1000), host({0x30, 0x00, 0x00}));
  EXPECT_EQ(sender.error(), IsoTpSendError::timeout);
}

// ---------------------------------------------------------------------------------------------
// STmin encoding

TEST(IsoTpStMin, Decode_MillisecondsMicrosecondsAndReserved) {
  EXPECT_EQ(decode_st_min(0x00), base::SimTime::zero());
  EXPECT_EQ(decode_st_min(0x01), milliseconds(1));
  EXPECT_EQ(decode_st_min(0x7F), milliseconds(127));
  EXPECT_EQ(decode_st_min(0xF1), microseconds(100));
  EXPECT_EQ(decode_st_min(0xF9), microseconds(900));
  for (std::uint8_t reserved : {0x80, 0xAA, 0xF0, 0xFA, 0xFF}) {
    EXPECT_EQ(decode_st_min(reserved), milliseconds(127)) << int{reserved};
  }
}

TEST(IsoTpStMin, Encode_RoundsUpAndClamps) {
  EXPECT_EQ(encode_st_min(base::SimTime::zero()), 0x00);
  EXPECT_EQ(encode_st_min(microseconds(100)), 0xF1);
  EXPECT_EQ(encode_st_min(microseconds(250)), 0xF3);
  EXPECT_EQ(encode_st_min(microseconds(900)), 0xF9);
  EXPECT_EQ(encode_st_min(microseconds(901)), 0x01);
  EXPECT_EQ(encode_st_min(milliseconds(1)), 0x01);
  EXPECT_EQ(encode_st_min(microseconds(1500)), 0x02);
  EXPECT_EQ(encode_st_min(milliseconds(127)), 0x7F);
  EXPECT_EQ(encode_st_min(milliseconds(500)), 0x7F);
}

TEST(IsoTpStMin, EncodeThenDecode_NeverFaster) {
  for (int us = 0; us <= 130000; us += 37) {
    const base::SimTime wanted = microseconds(us);
    const base::SimTime got = decode_st_min(encode_st_min(wanted));
    EXPECT_GE(got, std::min<base::SimTime>(wanted, kIsoTpMaxStMin)) << us << " us";
  }
}

TEST(IsoTpFrameType, PciNibble_Classified) {
  EXPECT_EQ(isotp_frame_type(host({0x01, 0x00})), IsoTpFrameType::single_frame);
  EXPECT_EQ(isotp_frame_type(host({0x10, 0x08, 0, 0, 0, 0, 0, 0})), IsoTpFrameType::first_frame);
  EXPECT_EQ(isotp_frame_type(host({0x2F})), IsoTpFrameType::consecutive_frame);
  EXPECT_EQ(isotp_frame_type(host({0x30, 0, 0})), IsoTpFrameType::flow_control);
  EXPECT_FALSE(isotp_frame_type(host({0x40})).has_value());
  EXPECT_FALSE(isotp_frame_type(host({})).has_value());
}

// ---------------------------------------------------------------------------------------------
// Random round trips

TEST(IsoTpRoundTrip, RandomLengthsUpTo9000_ReassembledExactly) {
  std::mt19937 random(20130601u);  // fixed seed: the same lengths on every run
  std::uniform_int_distribution<std::size_t> length_of(1, 9000);
  std::uniform_int_distribution<int> byte_of(0, 255);
  std::uniform_int_distribution<int> block_size_of(0, 20);
  std::uniform_int_distribution<int> st_min_us_of(0, 3000);
  for (int round = 0; round < 60; ++round) {
    const std::size_t length = round == 0 ? 9000 : length_of(random);
    Bytes message(length);
    for (auto& byte : message) {
      byte = static_cast<std::uint8_t>(byte_of(random));
    }
    const bool pad = (round % 2) == 1;
    IsoTpSender sender(sender_config(pad));
    IsoTpReceiverConfig config = receiver_config(
        static_cast<std::uint8_t>(block_size_of(random)), microseconds(st_min_us_of(random)));
    config.pad_frames = pad;
    IsoTpReceiver receiver(config);
    const Transfer transfer = run_transfer(sender, receiver, message, milliseconds(round));
    ASSERT_EQ(transfer.messages.size(), 1u) << "length " << length;
    EXPECT_EQ(transfer.messages[0], message) << "length " << length;
    EXPECT_EQ(transfer.final_state, IsoTpSender::State::done);
    EXPECT_EQ(receiver.counters().errors(), 0u);
    const std::size_t expected_frames =
        length <= 7 ? 1 : (length > 4095 ? 1 + (length - 2 + 6) / 7 : 1 + (length - 6 + 6) / 7);
    EXPECT_EQ(transfer.data_frames.size(), expected_frames) << "length " << length;
  }
}

}  // namespace
}  // namespace ldoem::protocol
