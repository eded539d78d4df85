// ISO-TP (D1) frame by frame: single frames, first and consecutive frames written out byte by
// byte, the 12-bit and escaped first-frame lengths, sequence numbers and what the receiver does
// with frames out of order. Flow control, timeouts and STmin: isotp_flow_test.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <vector>

#include "isotp_test_support.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::protocol {
namespace {

using namespace isotp_test;
using std::chrono::milliseconds;

// ---------------------------------------------------------------------------------------------
// Single frames

TEST(IsoTpSender, SingleFrameUnpadded_IsPciPlusData) {
  IsoTpSender sender(sender_config());
  const std::vector<CanFrame> frames = start_and_poll(sender, {}, Bytes{0x02, 0x01, 0x00});
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], device({0x03, 0x02, 0x01, 0x00}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::done);
  EXPECT_FALSE(sender.deadline().has_value());
}

TEST(IsoTpSender, SingleFramePadded_FillsWithCC) {
  IsoTpSender sender(sender_config(/*pad_frames=*/true));
  const std::vector<CanFrame> frames = start_and_poll(sender, {}, Bytes{0x02, 0x01});
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], device({0x02, 0x02, 0x01, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC}));
}

TEST(IsoTpSender, SevenBytes_FitOneSingleFrame) {
  IsoTpSender sender(sender_config());
  const std::vector<CanFrame> frames = start_and_poll(sender, {}, counting_bytes(7, 0xA0));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], device({0x07, 0xA0, 0xA1, 0xA2, 0xA3, 0xA4, 0xA5, 0xA6}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::done);
}

TEST(IsoTpSender, EmptyMessage_Refused) {
  IsoTpSender sender(sender_config());
  const auto started = sender.start({}, Bytes{});
  ASSERT_FALSE(started.has_value());
  EXPECT_EQ(started.error(), IsoTpSendError::empty_message);
  EXPECT_EQ(sender.state(), IsoTpSender::State::idle);
}

TEST(IsoTpReceiver, SingleFrameUnpadded_CompletesMessage) {
  IsoTpReceiver receiver(receiver_config());
  const IsoTpReceiveResult result = receiver.on_frame({}, host({0x02, 0x04, 0x01}));
  ASSERT_TRUE(result.message.has_value());
  EXPECT_EQ(*result.message, (Bytes{0x04, 0x01}));
  EXPECT_FALSE(result.flow_control.has_value());
  EXPECT_FALSE(result.error.has_value());
  EXPECT_EQ(receiver.counters().messages, 1u);
}

TEST(IsoTpReceiver, SingleFramePadded_PaddingIgnored) {
  IsoTpReceiver receiver(receiver_config());
  const IsoTpReceiveResult result =
      receiver.on_frame({}, host({0x02, 0x04, 0x01, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC}));
  ASSERT_TRUE(result.message.has_value());
  EXPECT_EQ(*result.message, (Bytes{0x04, 0x01}));
}

TEST(IsoTpReceiver, SingleFrameLengthsOneToSeven_RoundTrip) {
  for (std::size_t length = 1; length <= 7; ++length) {
    IsoTpSender sender(sender_config());
    IsoTpReceiver receiver(receiver_config());
    const Transfer transfer = run_transfer(sender, receiver, counting_bytes(length, 0x10));
    ASSERT_EQ(transfer.messages.size(), 1u) << "length " << length;
    EXPECT_EQ(transfer.messages[0], counting_bytes(length, 0x10));
    EXPECT_EQ(transfer.data_frames.size(), 1u);
    EXPECT_EQ(transfer.data_frames[0].frame.length, length + 1);
    EXPECT_TRUE(transfer.flow_control_frames.empty());
  }
}

TEST(IsoTpReceiver, SingleFrameBadLength_MalformedAndIgnored) {
  IsoTpReceiver receiver(receiver_config());
  const CanFrame bad_frames[] = {
      host({0x00, 0x11}),                                      // SF_DL 0: CAN FD escape
      host({0x08, 1, 2, 3, 4, 5, 6, 7}),                       // SF_DL 8 cannot fit
      host({0x03, 0x01, 0x02}),                                // DLC shorter than SF_DL + 1
      host({}),                                                // empty frame
      host({0x41, 0x00}),                                      // PCI type 4 is not ISO-TP
  };
  for (const CanFrame& bad : bad_frames) {
    const IsoTpReceiveResult result = receiver.on_frame({}, bad);
    EXPECT_FALSE(result.message.has_value());
    EXPECT_FALSE(result.flow_control.has_value());
    EXPECT_EQ(result.error, IsoTpReceiveError::malformed);
  }
  EXPECT_EQ(receiver.counters().malformed, std::size(bad_frames));
  EXPECT_EQ(receiver.counters().messages, 0u);
}

TEST(IsoTpReceiver, DlcAboveEight_Malformed) {
  IsoTpReceiver receiver(receiver_config());
  CanFrame too_long = host({0x01, 0x55});
  too_long.length = 9;
  EXPECT_EQ(receiver.on_frame({}, too_long).error, IsoTpReceiveError::malformed);
}

// ---------------------------------------------------------------------------------------------
// First frame, flow control, consecutive frames: a 20-byte message 00 01 .. 13

TEST(IsoTpSender, TwentyBytes_FirstFrameThenConsecutiveFramesAfterFlowControl) {
  IsoTpSender sender(sender_config());
  const std::vector<CanFrame> first = start_and_poll(sender, {}, counting_bytes(20));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0], device({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::waiting_for_flow_control);
  EXPECT_TRUE(sender.poll(milliseconds(5)).frames.empty());

  sender.on_flow_control(milliseconds(5), host({0x30, 0x00, 0x00}));
  const std::vector<CanFrame> rest = sender.poll(milliseconds(5)).frames;
  ASSERT_EQ(rest.size(), 2u);
  EXPECT_EQ(rest[0], device({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
  EXPECT_EQ(rest[1], device({0x22, 0x0D, 0x0E, 0x0F, 0x10, 0x11, 0x12, 0x13}));
  EXPECT_EQ(sender.state(), IsoTpSender::State::done);
}

TEST(IsoTpSender, LastConsecutiveFrameShort_UnpaddedOrPadded) {
  IsoTpSender unpadded(sender_config(false));
  (void)start_and_poll(unpadded, {}, counting_bytes(21));
  unpadded.on_flow_control({}, host({0x30, 0x00, 0x00}));
  const std::vector<CanFrame> unpadded_frames = unpadded.poll({}).frames;
  ASSERT_EQ(unpadded_frames.size(), 3u);
  EXPECT_EQ(unpadded_frames[2], device({0x23, 0x14}));

  IsoTpSender padded(sender_config(true));
  (void)start_and_poll(padded, {}, counting_bytes(21));
  padded.on_flow_control({}, host({0x30, 0x00, 0x00}));
  const std::vector<CanFrame> padded_frames = padded.poll({}).frames;
  ASSERT_EQ(padded_frames.size(), 3u);
  EXPECT_EQ(padded_frames[2], device({0x23, 0x14, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC}));
}

TEST(IsoTpReceiver, TwentyBytes_FlowControlThenMessage) {
  IsoTpReceiver receiver(receiver_config());
  const IsoTpReceiveResult first =
      receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  ASSERT_TRUE(first.flow_control.has_value());
  EXPECT_EQ(*first.flow_control, device({0x30, 0x00, 0x00}));  // D1: BS 0, STmin 0, 3 bytes
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::receiving);

  const IsoTpReceiveResult middle =
      receiver.on_frame({}, host({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
  EXPECT_TRUE(middle.nothing());
  const IsoTpReceiveResult last =
      receiver.on_frame({}, host({0x22, 0x0D, 0x0E, 0x0F, 0x10, 0x11, 0x12, 0x13}));
  ASSERT_TRUE(last.message.has_value());
  EXPECT_EQ(*last.message, counting_bytes(20));
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
  EXPECT_FALSE(receiver.deadline().has_value());
}

TEST(IsoTpReceiver, LastConsecutiveFramePaddedOrNot_SameMessage) {
  for (const CanFrame& last : {host({0x23, 0x14}),
                               host({0x23, 0x14, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC})}) {
    IsoTpReceiver receiver(receiver_config());
    (void)receiver.on_frame({}, host({0x10, 0x15, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
    (void)receiver.on_frame({}, host({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
    (void)receiver.on_frame({}, host({0x22, 0x0D, 0x0E, 0x0F, 0x10, 0x11, 0x12, 0x13}));
    const IsoTpReceiveResult result = receiver.on_frame({}, last);
    ASSERT_TRUE(result.message.has_value());
    EXPECT_EQ(*result.message, counting_bytes(21));
  }
}

TEST(IsoTpReceiver, PaddedFlowControl_WhenConfigured) {
  IsoTpReceiverConfig config = receiver_config(8, milliseconds(1));
  config.pad_frames = true;
  IsoTpReceiver receiver(config);
  const IsoTpReceiveResult first =
      receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  ASSERT_TRUE(first.flow_control.has_value());
  EXPECT_EQ(*first.flow_control, device({0x30, 0x08, 0x01, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC}));
}

TEST(IsoTpReceiver, ConsecutiveFrameTooShort_MalformedAndDropped) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  const IsoTpReceiveResult result = receiver.on_frame({}, host({0x21, 0x06, 0x07}));
  EXPECT_EQ(result.error, IsoTpReceiveError::malformed);
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
}

TEST(IsoTpReceiver, FirstFrameInvalid_Malformed) {
  IsoTpReceiver receiver(receiver_config());
  const CanFrame bad_frames[] = {
      host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04}),        // FF shorter than 8 bytes
      host({0x10, 0x07, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}),  // FF_DL 7 fits a single frame
      host({0x10, 0x00, 0x00, 0x00, 0x0F, 0xFF, 0x00, 0x01}),  // escape used for 4095
  };
  for (const CanFrame& bad : bad_frames) {
    const IsoTpReceiveResult result = receiver.on_frame({}, bad);
    EXPECT_EQ(result.error, IsoTpReceiveError::malformed);
    EXPECT_FALSE(result.flow_control.has_value());
  }
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
}

// ---------------------------------------------------------------------------------------------
// First frame length: 12 bits up to 4095, the 32-bit escape above

TEST(IsoTpSender, Length4095_TwelveBitFirstFrame) {
  IsoTpSender sender(sender_config());
  const std::vector<CanFrame> first = start_and_poll(sender, {}, counting_bytes(4095));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0], device({0x1F, 0xFF, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
}

TEST(IsoTpSender, Length4096_EscapedFirstFrame) {
  IsoTpSender sender(sender_config());
  const std::vector<CanFrame> first = start_and_poll(sender, {}, counting_bytes(4096));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0], device({0x10, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x01}));
}

TEST(IsoTpSender, Length5800_EscapedFirstFrameThenConsecutiveFromByteTwo) {
  IsoTpSender sender(sender_config());
  const std::vector<CanFrame> first = start_and_poll(sender, {}, counting_bytes(5800));
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0], device({0x10, 0x00, 0x00, 0x00, 0x16, 0xA8, 0x00, 0x01}));
  sender.on_flow_control({}, host({0x30, 0x01, 0x00}));
  const std::vector<CanFrame> next = sender.poll({}).frames;
  ASSERT_EQ(next.size(), 1u);
  EXPECT_EQ(next[0], device({0x21, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08}));
}

TEST(IsoTpReceiver, EscapedFirstFrame_AcceptedWithFlowControl) {
  IsoTpReceiver receiver(receiver_config());
  const IsoTpReceiveResult result =
      receiver.on_frame({}, host({0x10, 0x00, 0x00, 0x00, 0x16, 0xA8, 0xAA, 0xBB}));
  EXPECT_FALSE(result.error.has_value());
  ASSERT_TRUE(result.flow_control.has_value());
  EXPECT_EQ(*result.flow_control, device({0x30, 0x00, 0x00}));
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::receiving);
}

// The 5.8 kB profile of D1 with the host pacing BS = 8, STmin = 1 ms.
TEST(IsoTpRoundTrip, Profile5800BytesBlockSize8StMin1ms_FrameCountAndTiming) {
  IsoTpSender sender(sender_config());
  IsoTpReceiver receiver(receiver_config(8, milliseconds(1)));
  const base::SimTime start = milliseconds(100);
  const Bytes profile = counting_bytes(5800, 0x37);
  const Transfer transfer = run_transfer(sender, receiver, profile, start);

  ASSERT_EQ(transfer.messages.size(), 1u);
  EXPECT_EQ(transfer.messages[0], profile);
  EXPECT_EQ(transfer.final_state, IsoTpSender::State::done);

  // FF carries 2 bytes, then ceil(5798 / 7) = 829 CFs.
  constexpr std::size_t kConsecutiveFrames = 829;
  ASSERT_EQ(transfer.data_frames.size(), 1 + kConsecutiveFrames);
  // One FC after the FF and one after each full block of 8 CFs that is not the end.
  EXPECT_EQ(transfer.flow_control_frames.size(), 1 + (kConsecutiveFrames - 1) / 8);
  for (const TimedFrame& fc : transfer.flow_control_frames) {
    EXPECT_EQ(fc.frame, device({0x30, 0x08, 0x01}));
  }

  EXPECT_EQ(transfer.data_frames[0].at, start);
  // STmin separates every two CFs, across block boundaries too: CF k goes at start + k ms.
  for (std::size_t k = 0; k < kConsecutiveFrames; ++k) {
    const TimedFrame& cf = transfer.data_frames[1 + k];
    EXPECT_EQ(cf.at, start + milliseconds(k)) << "CF " << k;
    EXPECT_EQ(cf.frame.data[0], 0x20 | ((k + 1) & 0x0F)) << "CF " << k;
  }
  // 5798 = 828 * 7 + 2: the last CF holds 2 bytes and is not padded.
  EXPECT_EQ(transfer.data_frames.back().frame.length, 3);
  EXPECT_EQ(receiver.counters().errors(), 0u);
}

TEST(IsoTpRoundTrip, Length4096And4095And8_Reassembled) {
  for (std::size_t length : {std::size_t{8}, std::size_t{4095}, std::size_t{4096}}) {
    IsoTpSender sender(sender_config());
    IsoTpReceiver receiver(receiver_config());
    const Transfer transfer = run_transfer(sender, receiver, counting_bytes(length, 3));
    ASSERT_EQ(transfer.messages.size(), 1u) << length;
    EXPECT_EQ(transfer.messages[0], counting_bytes(length, 3));
  }
}

// ---------------------------------------------------------------------------------------------
// Sequence numbers

TEST(IsoTpSender, SequenceNumber_WrapsFrom15To0) {
  IsoTpSender sender(sender_config());
  (void)start_and_poll(sender, {}, counting_bytes(6 + 7 * 18));
  sender.on_flow_control({}, host({0x30, 0x00, 0x00}));
  const std::vector<CanFrame> frames = sender.poll({}).frames;
  ASSERT_EQ(frames.size(), 18u);
  const std::uint8_t expected_pci[] = {0x21, 0x22, 0x23, 0x24, 0x25, 0x26, 0x27, 0x28, 0x29,
                                       0x2A, 0x2B, 0x2C, 0x2D, 0x2E, 0x2F, 0x20, 0x21, 0x22};
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].data[0], expected_pci[i]) << "CF " << i;
  }
}

TEST(IsoTpReceiver, SequenceWrapPast15_Reassembled) {
  IsoTpReceiver receiver(receiver_config());
  const Bytes message = counting_bytes(6 + 7 * 18);
  (void)receiver.on_frame({}, host({0x10, 0x84, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  IsoTpReceiveResult result;
  for (std::size_t i = 0; i < 18; ++i) {
    CanFrame cf;
    cf.id = kRequestId;
    cf.length = 8;
    cf.data[0] = static_cast<std::uint8_t>(0x20 | ((i + 1) & 0x0F));
    for (std::size_t b = 0; b < 7; ++b) {
      cf.data[1 + b] = message[6 + 7 * i + b];
    }
    result = receiver.on_frame({}, cf);
    ASSERT_FALSE(result.error.has_value()) << "CF " << i;
  }
  ASSERT_TRUE(result.message.has_value());
  EXPECT_EQ(*result.message, message);
}

TEST(IsoTpReceiver, WrongSequenceNumber_DroppedAndCounted) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  const IsoTpReceiveResult skipped =
      receiver.on_frame({}, host({0x22, 0x0D, 0x0E, 0x0F, 0x10, 0x11, 0x12, 0x13}));
  EXPECT_EQ(skipped.error, IsoTpReceiveError::bad_sequence);
  EXPECT_FALSE(skipped.flow_control.has_value());  // D1: nothing is sent
  EXPECT_FALSE(skipped.message.has_value());
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
  EXPECT_EQ(receiver.counters().bad_sequence, 1u);

  // The rest of the broken telegram is unexpected now, and the next telegram works.
  const IsoTpReceiveResult stray =
      receiver.on_frame({}, host({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
  EXPECT_EQ(stray.error, IsoTpReceiveError::unexpected_frame);
  EXPECT_TRUE(receiver.on_frame({}, host({0x01, 0x42})).message.has_value());
}

TEST(IsoTpReceiver, ConsecutiveFrameWithoutFirstFrame_UnexpectedAndCounted) {
  IsoTpReceiver receiver(receiver_config());
  const IsoTpReceiveResult result =
      receiver.on_frame({}, host({0x21, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B, 0x0C}));
  EXPECT_EQ(result.error, IsoTpReceiveError::unexpected_frame);
  EXPECT_FALSE(result.flow_control.has_value());
  EXPECT_EQ(receiver.counters().unexpected_frame, 1u);
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
}

TEST(IsoTpReceiver, SingleFrameDuringReception_DropsPartialAndDelivers) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  const IsoTpReceiveResult result = receiver.on_frame({}, host({0x02, 0x04, 0x01}));
  EXPECT_EQ(result.error, IsoTpReceiveError::unexpected_frame);
  ASSERT_TRUE(result.message.has_value());
  EXPECT_EQ(*result.message, (Bytes{0x04, 0x01}));
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::idle);
}

TEST(IsoTpReceiver, FirstFrameDuringReception_RestartsReception) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x14, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05}));
  const IsoTpReceiveResult restart =
      receiver.on_frame({}, host({0x10, 0x08, 0xA0, 0xA1, 0xA2, 0xA3, 0xA4, 0xA5}));
  EXPECT_EQ(restart.error, IsoTpReceiveError::unexpected_frame);
  ASSERT_TRUE(restart.flow_control.has_value());
  const IsoTpReceiveResult done = receiver.on_frame({}, host({0x21, 0xA6, 0xA7}));
  ASSERT_TRUE(done.message.has_value());
  EXPECT_EQ(*done.message, counting_bytes(8, 0xA0));
}

TEST(IsoTpReceiver, MalformedFrameDuringReception_ReceptionContinues) {
  IsoTpReceiver receiver(receiver_config());
  (void)receiver.on_frame({}, host({0x10, 0x08, 0xA0, 0xA1, 0xA2, 0xA3, 0xA4, 0xA5}));
  EXPECT_EQ(receiver.on_frame({}, host({0x00})).error, IsoTpReceiveError::malformed);
  EXPECT_EQ(receiver.state(), IsoTpReceiver::State::receiving);
  EXPECT_TRUE(receiver.on_frame({}, host({0x21, 0xA6, 0xA7})).message.has_value());
}

TEST(IsoTpReceiver, FlowControlFrame_IgnoredByReceiver) {
  IsoTpReceiver receiver(receiver_config());
  EXPECT_TRUE(receiver.on_frame({}, host({0x30, 0x00, 0x00})).nothing());
  EXPECT_EQ(receiver.counters().errors(), 0u);
}

}  // namespace
}  // namespace ldoem::protocol
