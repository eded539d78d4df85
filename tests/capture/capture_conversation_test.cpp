// From captured packets to telegrams: TCP reassembled across segments (with retransmissions and
// lost bytes), ISO-TP on the D1 identifiers, serial in both directions.
#include <gtest/gtest.h>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/protocol/isotp.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "test_support.hpp"

namespace ldoem::capture {
namespace {

using protocol::test::hex;
using protocol::test::kStatusReply;
using std::chrono::milliseconds;

const protocol::Bytes kGetStatus = hex("01 02");

TcpSegment to_device(std::uint32_t sequence, protocol::ByteView payload, std::uint16_t host_port = 40000) {
  return TcpSegment{0x7F000001, 0x7F000002, host_port, base::kHostTcpPort, sequence, 0, kTcpAck, protocol::Bytes(payload.begin(), payload.end())};
}
TcpSegment to_host(std::uint32_t sequence, protocol::ByteView payload, std::uint16_t host_port = 40000) {
  return TcpSegment{0x7F000002, 0x7F000001, base::kHostTcpPort, host_port, sequence, 0, kTcpAck, protocol::Bytes(payload.begin(), payload.end())};
}

TEST(Conversation, TcpFramesSplitOverSegments_AreReassembledPerDirection) {
  const protocol::Bytes request = protocol::encode_tcp_frame(kGetStatus);
  const protocol::Bytes reply = protocol::encode_tcp_frame(kStatusReply);
  std::vector<DecodedPacket> packets;
  packets.push_back({milliseconds(1), to_device(100, protocol::ByteView(request).first(5))});
  packets.push_back({milliseconds(2), to_device(105, protocol::ByteView(request).subspan(5))});
  packets.push_back({milliseconds(3), to_host(7, reply)});
  const Conversation conversation = extract_conversation(packets);
  ASSERT_EQ(conversation.telegrams.size(), 2u);
  EXPECT_EQ(conversation.telegrams[0],
            (CapturedTelegram{milliseconds(2), protocol::Transport::tcp, protocol::WireDirection::host_to_device, 0, kGetStatus}));
  EXPECT_EQ(conversation.telegrams[1],
            (CapturedTelegram{milliseconds(3), protocol::Transport::tcp, protocol::WireDirection::device_to_host, 0, kStatusReply}));
}

TEST(Conversation, RetransmittedBytes_AreDeliveredOnce) {
  const protocol::Bytes request = protocol::encode_tcp_frame(kGetStatus);
  std::vector<DecodedPacket> packets;
  packets.push_back({milliseconds(1), to_device(1, protocol::ByteView(request).first(6))});
  packets.push_back({milliseconds(2), to_device(1, request)});  // overlaps the first six bytes
  packets.push_back({milliseconds(3), to_device(1, request)});  // pure retransmission
  const Conversation conversation = extract_conversation(packets);
  ASSERT_EQ(conversation.telegrams.size(), 1u);
  EXPECT_EQ(conversation.telegrams[0].payload, kGetStatus);
}

TEST(Conversation, LostBytes_CountAGapAndResynchronise) {
  const protocol::Bytes first = protocol::encode_tcp_frame(kGetStatus);
  const protocol::Bytes second = protocol::encode_tcp_frame(hex("04 02"));
  std::vector<DecodedPacket> packets;
  packets.push_back({milliseconds(1), to_device(1, protocol::ByteView(first).first(4))});
  packets.push_back({milliseconds(2), to_device(1 + static_cast<std::uint32_t>(first.size()), second)});
  const Conversation conversation = extract_conversation(packets);
  ASSERT_EQ(conversation.telegrams.size(), 1u);
  EXPECT_EQ(conversation.telegrams[0].payload, hex("04 02"));
  EXPECT_EQ(conversation.counters.tcp_gaps, 1u);
}

TEST(Conversation, TwoConnections_GetTheirOwnStreamIndex) {
  std::vector<DecodedPacket> packets;
  packets.push_back({milliseconds(1), to_device(1, protocol::encode_tcp_frame(kGetStatus), 40000)});
  packets.push_back({milliseconds(2), to_device(1, protocol::encode_tcp_frame(kGetStatus), 40001)});
  TcpSegment other_port = to_device(1, protocol::encode_tcp_frame(kGetStatus));
  other_port.destination_port = 80;
  packets.push_back({milliseconds(3), other_port});
  const Conversation conversation = extract_conversation(packets);
  ASSERT_EQ(conversation.telegrams.size(), 2u);
  EXPECT_EQ(conversation.telegrams[0].stream, 0u);
  EXPECT_EQ(conversation.telegrams[1].stream, 1u);
  EXPECT_EQ(conversation.counters.ignored_packets, 1u);
}

TEST(Conversation, BadChecksum_IsCountedNotDelivered) {
  protocol::Bytes frame = protocol::encode_tcp_frame(kGetStatus);
  frame.back() ^= 0xFF;
  const Conversation conversation = extract_conversation({{milliseconds(1), to_device(1, frame)}});
  EXPECT_TRUE(conversation.telegrams.empty());
  EXPECT_EQ(conversation.counters.framing_errors, 1u);
}

TEST(Conversation, IsoTpOnD1Identifiers_ReassemblesALongReply) {
  protocol::Bytes reply = hex("83 01 39 FF");
  for (int i = 0; i < 40; ++i) reply.push_back(static_cast<std::uint8_t>(i));
  protocol::IsoTpSender sender({.data_id = protocol::kIsoTpDeviceToHostId});
  ASSERT_TRUE(sender.start(base::SimTime{}, reply).has_value());
  std::vector<DecodedPacket> packets;
  packets.push_back({milliseconds(1), *protocol::make_can_frame(protocol::kIsoTpHostToDeviceId, hex("02 01 02"))});
  protocol::IsoTpSendPoll poll = sender.poll(base::SimTime{});
  for (const auto& frame : poll.frames) packets.push_back({milliseconds(2), frame});
  // The host's flow control on 0x6C0 is not a request.
  const protocol::CanFrame flow_control = protocol::make_flow_control_frame(protocol::kIsoTpHostToDeviceId, protocol::IsoTpFlowStatus::continue_to_send, 0, 0, false);
  packets.push_back({milliseconds(3), flow_control});
  sender.on_flow_control(milliseconds(3), flow_control);
  poll = sender.poll(milliseconds(3));
  for (const auto& frame : poll.frames) packets.push_back({milliseconds(4), frame});
  packets.push_back({milliseconds(5), *protocol::make_can_frame(0x123, hex("01 02"))});
  const Conversation conversation = extract_conversation(packets);
  ASSERT_EQ(conversation.telegrams.size(), 2u);
  EXPECT_EQ(conversation.telegrams[0],
            (CapturedTelegram{milliseconds(1), protocol::Transport::can, protocol::WireDirection::host_to_device, 0, kGetStatus}));
  EXPECT_EQ(conversation.telegrams[1].payload, reply);
  EXPECT_EQ(conversation.telegrams[1].direction, protocol::WireDirection::device_to_host);
  EXPECT_EQ(conversation.counters.ignored_packets, 1u);
  EXPECT_EQ(conversation.counters.framing_errors, 0u);
}

TEST(Conversation, Serial_DeframesRequestsAndReassemblesReplies) {
  std::vector<DecodedPacket> packets;
  packets.push_back({milliseconds(1), SerialChunk{protocol::WireDirection::host_to_device, protocol::encode_serial_request(kGetStatus)}});
  packets.push_back({milliseconds(2), SerialChunk{protocol::WireDirection::device_to_host, protocol::encode_serial_reply(kStatusReply)}});
  packets.push_back({milliseconds(3), LptWrites{hex("02 03")}});
  const Conversation conversation = extract_conversation(packets);
  ASSERT_EQ(conversation.telegrams.size(), 2u);
  EXPECT_EQ(conversation.telegrams[0].payload, kGetStatus);
  EXPECT_EQ(conversation.telegrams[0].transport, protocol::Transport::serial);
  EXPECT_EQ(conversation.telegrams[1].payload, kStatusReply);
  EXPECT_EQ(conversation.counters.lpt_writes, 2u);
}

}  // namespace
}  // namespace ldoem::capture
