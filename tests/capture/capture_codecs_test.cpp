// The capture codecs (capture/, docs/capture.md): pcapng blocks, the per-link packet
// payloads (SocketCAN, synthesized IPv4/TCP, serial, LPT) and the candump log line grammar.
#include <gtest/gtest.h>

#include "ldoem/capture/candump_log.hpp"
#include "ldoem/capture/capture_packets.hpp"
#include "ldoem/capture/pcapng.hpp"
#include "test_support.hpp"

namespace ldoem::capture {
namespace {

using protocol::test::hex;

protocol::Bytes concat_blocks(std::initializer_list<protocol::Bytes> blocks) {
  protocol::Bytes out;
  for (const auto& block : blocks) out.insert(out.end(), block.begin(), block.end());
  return out;
}

TEST(Pcapng, SectionHeader_IsLittleEndianWithByteOrderMagicAndMatchingLengths) {
  const protocol::Bytes block = encode_pcapng_section_header("");
  ASSERT_EQ(block.size(), 32u);  // 12 overhead + 16 body + end-of-options
  EXPECT_EQ(protocol::Bytes(block.begin(), block.begin() + 12), hex("0A 0D 0D 0A 20 00 00 00 4D 3C 2B 1A"));
  EXPECT_EQ(protocol::Bytes(block.end() - 4, block.end()), hex("20 00 00 00"));
}

TEST(Pcapng, PacketBlock_PadsDataAndCarriesDirectionFlags) {
  const protocol::Bytes block = encode_pcapng_packet(1, 0x0000000100000002ull, hex("AA BB CC"), PacketDirection::outbound);
  // 12 overhead + 20 fixed + 4 data (3 padded) + flags option 8 + end 4.
  ASSERT_EQ(block.size(), 48u);
  EXPECT_EQ(protocol::Bytes(block.begin() + 8, block.begin() + 36),
            hex("01 00 00 00 01 00 00 00 02 00 00 00 03 00 00 00 03 00 00 00 AA BB CC 00 02 00 04 00"));
}

TEST(Pcapng, RoundTrip_KeepsLinkTypesTimesDirectionsAndData) {
  const protocol::Bytes file = concat_blocks({
      encode_pcapng_section_header("test"),
      encode_pcapng_interface(LinkType::can_socketcan, "can"),
      encode_pcapng_interface(LinkType::ipv4, "tcp"),
      encode_pcapng_packet(1, 1'500'000'000ull, hex("01 02 03 04 05"), PacketDirection::inbound),
      encode_pcapng_packet(0, 7, hex(""), PacketDirection::unknown),
  });
  const auto packets = decode_pcapng(file);
  ASSERT_TRUE(packets.has_value()) << describe(packets.error().error);
  ASSERT_EQ(packets->size(), 2u);
  EXPECT_EQ((*packets)[0], (CapturePacket{LinkType::ipv4, 1, 1'500'000'000ull, PacketDirection::inbound, hex("01 02 03 04 05")}));
  EXPECT_EQ((*packets)[1], (CapturePacket{LinkType::can_socketcan, 0, 7, PacketDirection::unknown, {}}));
}

TEST(Pcapng, MicrosecondInterfaceWithoutTsresol_IsScaledToNanoseconds) {
  // A hand-made IDB without options (default resolution 10^-6), then one EPB at 3 us.
  const protocol::Bytes idb = hex("01 00 00 00 14 00 00 00 E4 00 00 00 00 00 04 00 14 00 00 00");
  const protocol::Bytes file = concat_blocks({encode_pcapng_section_header(""), idb,
                                    encode_pcapng_packet(0, 3, hex("45"), PacketDirection::unknown)});
  const auto packets = decode_pcapng(file);
  ASSERT_TRUE(packets.has_value());
  ASSERT_EQ(packets->size(), 1u);
  EXPECT_EQ((*packets)[0].time_ns, 3000u);
}

TEST(Pcapng, BrokenFiles_AreTypedErrorsWithOffsets) {
  const protocol::Bytes good = concat_blocks({encode_pcapng_section_header(""), encode_pcapng_interface(LinkType::ipv4, ""),
                                    encode_pcapng_packet(0, 0, hex("01 02"), PacketDirection::unknown)});
  EXPECT_EQ(decode_pcapng(hex("D4 C3 B2 A1")).error().error, CaptureFormatError::not_pcapng);
  protocol::Bytes cut(good.begin(), good.end() - 3);
  EXPECT_EQ(decode_pcapng(cut).error().error, CaptureFormatError::truncated);
  protocol::Bytes bad_magic = good;
  bad_magic[8] = 0x00;
  EXPECT_EQ(decode_pcapng(bad_magic).error().error, CaptureFormatError::bad_byte_order);
  protocol::Bytes unknown_interface = good;
  const std::size_t epb = good.size() - encode_pcapng_packet(0, 0, hex("01 02"), PacketDirection::unknown).size();
  unknown_interface[epb + 8] = 5;
  const auto failure = decode_pcapng(unknown_interface);
  EXPECT_EQ(failure.error().error, CaptureFormatError::unknown_interface);
  EXPECT_EQ(failure.error().offset, epb);
  protocol::Bytes huge_caplen = good;
  huge_caplen[epb + 20] = 0xFF;
  EXPECT_EQ(decode_pcapng(huge_caplen).error().error, CaptureFormatError::bad_packet_length);
  protocol::Bytes odd_length = good;
  odd_length[epb + 4] = 0x1D;
  EXPECT_EQ(decode_pcapng(odd_length).error().error, CaptureFormatError::bad_block_length);
}

TEST(SocketCan, Packet_HasBigEndianIdLengthAndData) {
  const protocol::CanFrame frame = *protocol::make_can_frame(0x6C1, hex("10 16 83 01"));
  const protocol::Bytes packet = encode_socketcan_packet(frame);
  EXPECT_EQ(packet, hex("00 00 06 C1 04 00 00 00 10 16 83 01"));
  EXPECT_EQ(std::get<protocol::CanFrame>(decode_link_payload(LinkType::can_socketcan, packet)), frame);
}

TEST(SocketCan, ExtendedRemoteErrorAndFdFrames_AreIgnored) {
  EXPECT_TRUE(std::holds_alternative<std::monostate>(
      decode_link_payload(LinkType::can_socketcan, hex("80 00 06 C0 01 00 00 00 01"))));
  EXPECT_TRUE(std::holds_alternative<std::monostate>(
      decode_link_payload(LinkType::can_socketcan, hex("40 00 06 C0 00 00 00 00"))));
  EXPECT_TRUE(std::holds_alternative<std::monostate>(
      decode_link_payload(LinkType::can_socketcan, hex("00 00 06 C0 01 04 00 00 01"))));
  EXPECT_TRUE(std::holds_alternative<std::monostate>(
      decode_link_payload(LinkType::can_socketcan, hex("00 00 06 C0 09 00 00 00 01 02 03 04 05 06 07 08 09"))));
}

TEST(Ipv4Tcp, Synthesized_HasValidChecksumsAndDecodesBack) {
  TcpSegment segment{0x7F000001, 0x7F000002, 40000, 49152, 1, 1, kTcpAck | kTcpPsh, hex("02 55 53 50 00 00 00 02 01 02 03")};
  const protocol::Bytes packet = encode_ipv4_tcp_packet(segment);
  ASSERT_EQ(packet.size(), 51u);
  // A correct IPv4 header sums to 0xFFFF; so does the TCP segment with its pseudo header.
  std::uint32_t sum = 0;
  for (std::size_t i = 0; i < 20; i += 2) sum += protocol::read_word_be(packet, i);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  EXPECT_EQ(sum, 0xFFFFu);
  sum = 6 + 31;
  for (std::size_t i = 12; i < 20; i += 2) sum += protocol::read_word_be(packet, i);
  for (std::size_t i = 20; i + 1 < packet.size(); i += 2) sum += protocol::read_word_be(packet, i);
  sum += static_cast<std::uint32_t>(packet.back()) << 8;
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  EXPECT_EQ(sum, 0xFFFFu);
  EXPECT_EQ(std::get<TcpSegment>(decode_link_payload(LinkType::ipv4, packet)), segment);
}

TEST(Ipv4Tcp, BehindEthernetCookedAndLoopbackHeaders_Decodes) {
  TcpSegment segment{0x0A000001, 0x0A00000A, 5000, 49152, 99, 0, kTcpAck, hex("01 02")};
  const protocol::Bytes ip = encode_ipv4_tcp_packet(segment);
  protocol::Bytes ethernet = hex("00 11 22 33 44 55 66 77 88 99 AA BB 08 00");
  ethernet.insert(ethernet.end(), ip.begin(), ip.end());
  EXPECT_EQ(std::get<TcpSegment>(decode_link_payload(LinkType::ethernet, ethernet)), segment);
  protocol::Bytes sll = hex("00 00 03 04 00 06 00 00 00 00 00 00 00 00 08 00");
  sll.insert(sll.end(), ip.begin(), ip.end());
  EXPECT_EQ(std::get<TcpSegment>(decode_link_payload(LinkType::linux_sll, sll)), segment);
  protocol::Bytes loopback = hex("02 00 00 00");
  loopback.insert(loopback.end(), ip.begin(), ip.end());
  EXPECT_EQ(std::get<TcpSegment>(decode_link_payload(LinkType::null_loopback, loopback)), segment);
  protocol::Bytes fragment = ip;
  fragment[6] = 0x20;  // more fragments
  EXPECT_TRUE(std::holds_alternative<std::monostate>(decode_link_payload(LinkType::ipv4, fragment)));
}

TEST(SerialAndLpt, Packets_CarryDirectionThenBytes) {
  const SerialChunk chunk{protocol::WireDirection::device_to_host, hex("02 30 03")};
  EXPECT_EQ(encode_serial_packet(chunk), hex("01 02 30 03"));
  EXPECT_EQ(std::get<SerialChunk>(decode_link_payload(LinkType::user0, hex("01 02 30 03"))), chunk);
  EXPECT_EQ(std::get<LptWrites>(decode_link_payload(LinkType::user1, hex("00 03 01"))), (LptWrites{hex("03 01")}));
  EXPECT_TRUE(std::holds_alternative<std::monostate>(decode_link_payload(LinkType::user0, hex("07 02"))));
}

TEST(Candump, LogLine_ParsesTimeInterfaceIdAndData) {
  const auto entry = parse_candump_line("(1700000000.123456) vcan0 6C0#0301000039FF");
  ASSERT_TRUE(entry.has_value());
  EXPECT_EQ(entry->time_ns, 1'700'000'000'123'456'000ull);
  EXPECT_EQ(entry->interface, "vcan0");
  EXPECT_EQ(entry->frame, *protocol::make_can_frame(0x6C0, hex("03 01 00 00 39 FF")));
  EXPECT_FALSE(entry->extended_id);
}

TEST(Candump, FormatThenParse_IsTheSameFrame) {
  const protocol::CanFrame frame = *protocol::make_can_frame(0x6C1, hex("21 00 01 02 03 04 05 06"));
  const std::string line = format_candump_line(12'000'345'000ull, "vcan1", frame);
  EXPECT_EQ(line, "(12.000345) vcan1 6C1#2100010203040506");
  EXPECT_EQ(parse_candump_line(line)->frame, frame);
}

TEST(Candump, VariantsAndErrors) {
  EXPECT_TRUE(parse_candump_line("(1.5) can0 123#R")->remote);
  EXPECT_TRUE(parse_candump_line("(1.5) can0 12345678#00")->extended_id);
  EXPECT_TRUE(parse_candump_line("(1.500000) can0 123#11 R").has_value());
  EXPECT_EQ(parse_candump_line("1.5 can0 123#11").error(), CandumpError::bad_timestamp);
  EXPECT_EQ(parse_candump_line("(1.5) can0").error(), CandumpError::missing_field);
  EXPECT_EQ(parse_candump_line("(1.5) can0 800#11").error(), CandumpError::bad_identifier);
  EXPECT_EQ(parse_candump_line("(1.5) can0 12#11").error(), CandumpError::bad_identifier);
  EXPECT_EQ(parse_candump_line("(1.5) can0 123#1").error(), CandumpError::bad_data);
  EXPECT_EQ(parse_candump_line("(1.5) can0 123#1122334455667788AA").error(), CandumpError::bad_data);
  EXPECT_EQ(parse_candump_line("(1.5) can0 123#GG").error(), CandumpError::bad_data);
  EXPECT_EQ(parse_candump_line("(1.5) can0 123##1AA").error(), CandumpError::unsupported);
}

TEST(Candump, Log_SkipsBlankLinesAndNamesTheBadLine) {
  const auto log = parse_candump_log("(1.0) vcan0 6C0#0102\n\n(1.1) vcan0 6C1#06810200000001\n");
  ASSERT_TRUE(log.has_value());
  EXPECT_EQ(log->size(), 2u);
  const auto bad = parse_candump_log("(1.0) vcan0 6C0#0102\n(1.1) vcan0 6C1#0\n");
  ASSERT_FALSE(bad.has_value());
  EXPECT_EQ(bad.error().line, 2u);
  EXPECT_TRUE(looks_like_candump_log("(1.0) vcan0 6C0#0102"));
  EXPECT_FALSE(looks_like_candump_log("\x0A\x0D\x0D\x0A"));
}

}  // namespace
}  // namespace ldoem::capture
