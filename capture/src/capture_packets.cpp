#include "ldoem/capture/capture_packets.hpp"

namespace ldoem::capture {
namespace {

constexpr std::size_t kIpv4HeaderBytes = 20;
constexpr std::size_t kTcpHeaderBytes = 20;
constexpr std::uint8_t kIpProtocolTcp = 6;
constexpr std::uint16_t kEtherTypeIpv4 = 0x0800;
constexpr std::uint16_t kEtherTypeVlan = 0x8100;
constexpr std::size_t kEthernetHeaderBytes = 14;
constexpr std::size_t kLinuxSllHeaderBytes = 16;
constexpr std::size_t kLinuxSll2HeaderBytes = 20;
constexpr std::uint32_t kAfInet = 2;

// RFC 1071 one's-complement sum, folded.
std::uint32_t add_words(std::uint32_t sum, protocol::ByteView bytes) {
  for (std::size_t i = 0; i + 1 < bytes.size(); i += 2) sum += protocol::read_word_be(bytes, i);
  if (bytes.size() % 2 != 0) sum += static_cast<std::uint32_t>(bytes.back()) << 8;
  return sum;
}

std::uint16_t fold(std::uint32_t sum) {
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return static_cast<std::uint16_t>(~sum & 0xFFFF);
}

void put_word_at(protocol::Bytes& bytes, std::size_t at, std::uint16_t word) {
  bytes[at] = static_cast<std::uint8_t>(word >> 8);
  bytes[at + 1] = static_cast<std::uint8_t>(word & 0xFF);
}

LinkPayload decode_ipv4(protocol::ByteView packet) {
  if (packet.size() < kIpv4HeaderBytes || (packet[0] >> 4) != 4) return std::monostate{};
  const std::size_t header = std::size_t{packet[0] & 0x0Fu} * 4;
  const std::uint16_t total = protocol::read_word_be(packet, 2);
  if (header < kIpv4HeaderBytes || total < header || total > packet.size()) return std::monostate{};
  const std::uint16_t fragment = protocol::read_word_be(packet, 6);
  // More-fragments set or a non-zero offset: a fragment, never produced for our segments.
  if ((fragment & 0x3FFF) != 0 || packet[9] != kIpProtocolTcp) return std::monostate{};
  const protocol::ByteView tcp = packet.subspan(header, total - header);
  if (tcp.size() < kTcpHeaderBytes) return std::monostate{};
  const std::size_t tcp_header = static_cast<std::size_t>(tcp[12] >> 4) * 4;
  if (tcp_header < kTcpHeaderBytes || tcp_header > tcp.size()) return std::monostate{};
  TcpSegment segment;
  segment.source_ip = protocol::read_u32_be(packet, 12);
  segment.destination_ip = protocol::read_u32_be(packet, 16);
  segment.source_port = protocol::read_word_be(tcp, 0);
  segment.destination_port = protocol::read_word_be(tcp, 2);
  segment.sequence = protocol::read_u32_be(tcp, 4);
  segment.acknowledgement = protocol::read_u32_be(tcp, 8);
  segment.flags = tcp[13];
  segment.payload.assign(tcp.begin() + static_cast<std::ptrdiff_t>(tcp_header), tcp.end());
  return segment;
}

LinkPayload decode_ethertype(std::uint16_t ether_type, protocol::ByteView rest) {
  return ether_type == kEtherTypeIpv4 ? decode_ipv4(rest) : LinkPayload{std::monostate{}};
}

LinkPayload decode_socketcan(protocol::ByteView data) {
  if (data.size() < kSocketCanHeaderBytes) return std::monostate{};
  const std::uint32_t id = protocol::read_u32_be(data, 0);
  const std::uint8_t length = data[4];
  const std::uint8_t fd_flags = data[5];
  if ((id & (kSocketCanExtendedFlag | kSocketCanRemoteFlag | kSocketCanErrorFlag)) != 0 || fd_flags != 0 ||
      length > protocol::kCanMaxDataBytes || data.size() < kSocketCanHeaderBytes + length) {
    return std::monostate{};
  }
  if (auto frame = protocol::make_can_frame(id & protocol::kCanStandardIdMask, data.subspan(kSocketCanHeaderBytes, length))) {
    return *frame;
  }
  return std::monostate{};
}

}  // namespace

protocol::Bytes encode_socketcan_packet(const protocol::CanFrame& frame) {
  protocol::Bytes out;
  protocol::append_u32_be(out, frame.id & protocol::kCanStandardIdMask);
  const protocol::ByteView payload = frame.payload();
  out.push_back(static_cast<std::uint8_t>(payload.size()));
  out.push_back(0);  // FD flags: classic frame
  out.push_back(0);
  out.push_back(0);
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

protocol::Bytes encode_ipv4_tcp_packet(const TcpSegment& segment) {
  const std::size_t total = kIpv4HeaderBytes + kTcpHeaderBytes + segment.payload.size();
  protocol::Bytes out;
  out.reserve(total);
  out.push_back(0x45);  // IPv4, 5-word header
  out.push_back(0);
  protocol::append_word_be(out, static_cast<std::uint16_t>(total));
  protocol::append_word_be(out, 0);       // identification
  protocol::append_word_be(out, 0x4000);  // don't fragment
  out.push_back(64);            // TTL
  out.push_back(kIpProtocolTcp);
  protocol::append_word_be(out, 0);  // header checksum, filled below
  protocol::append_u32_be(out, segment.source_ip);
  protocol::append_u32_be(out, segment.destination_ip);
  put_word_at(out, 10, fold(add_words(0, protocol::ByteView(out).first(kIpv4HeaderBytes))));

  protocol::append_word_be(out, segment.source_port);
  protocol::append_word_be(out, segment.destination_port);
  protocol::append_u32_be(out, segment.sequence);
  protocol::append_u32_be(out, segment.acknowledgement);
  out.push_back(0x50);  // 5-word header
  out.push_back(segment.flags);
  protocol::append_word_be(out, 0xFFFF);  // window
  protocol::append_word_be(out, 0);       // checksum, filled below
  protocol::append_word_be(out, 0);       // urgent pointer
  out.insert(out.end(), segment.payload.begin(), segment.payload.end());

  const std::size_t tcp_length = total - kIpv4HeaderBytes;
  std::uint32_t sum = 0;
  sum = add_words(sum, protocol::ByteView(out).subspan(12, 8));  // pseudo header: addresses
  sum += kIpProtocolTcp;
  sum += static_cast<std::uint32_t>(tcp_length);
  sum = add_words(sum, protocol::ByteView(out).subspan(kIpv4HeaderBytes));
  put_word_at(out, kIpv4HeaderBytes + 16, fold(sum));
  return out;
}

protocol::Bytes encode_serial_packet(const SerialChunk& chunk) {
  protocol::Bytes out;
  out.reserve(chunk.bytes.size() + 1);
  out.push_back(static_cast<std::uint8_t>(chunk.direction));
  out.insert(out.end(), chunk.bytes.begin(), chunk.bytes.end());
  return out;
}

protocol::Bytes encode_lpt_packet(const LptWrites& writes) {
  protocol::Bytes out;
  out.reserve(writes.values.size() + 1);
  out.push_back(static_cast<std::uint8_t>(protocol::WireDirection::host_to_device));
  out.insert(out.end(), writes.values.begin(), writes.values.end());
  return out;
}

LinkPayload decode_link_payload(LinkType link_type, protocol::ByteView data) {
  switch (link_type) {
    case LinkType::can_socketcan:
      return decode_socketcan(data);
    case LinkType::raw_ip:
    case LinkType::ipv4:
      return decode_ipv4(data);
    case LinkType::ethernet: {
      if (data.size() < kEthernetHeaderBytes) return std::monostate{};
      std::uint16_t ether_type = protocol::read_word_be(data, 12);
      std::size_t offset = kEthernetHeaderBytes;
      if (ether_type == kEtherTypeVlan) {
        if (data.size() < kEthernetHeaderBytes + 4) return std::monostate{};
        ether_type = protocol::read_word_be(data, 16);
        offset += 4;
      }
      return decode_ethertype(ether_type, data.subspan(offset));
    }
    case LinkType::linux_sll:
      if (data.size() < kLinuxSllHeaderBytes) return std::monostate{};
      return decode_ethertype(protocol::read_word_be(data, 14), data.subspan(kLinuxSllHeaderBytes));
    case LinkType::linux_sll2:
      if (data.size() < kLinuxSll2HeaderBytes) return std::monostate{};
      return decode_ethertype(protocol::read_word_be(data, 0), data.subspan(kLinuxSll2HeaderBytes));
    case LinkType::null_loopback: {
      if (data.size() < 4) return std::monostate{};
      // The family is in the capturing host's byte order: accept AF_INET either way.
      const std::uint32_t family = protocol::read_u32_be(data, 0);
      const std::uint32_t swapped = (family >> 24) | ((family >> 8) & 0xFF00) | ((family << 8) & 0xFF0000) | (family << 24);
      if (family != kAfInet && swapped != kAfInet) return std::monostate{};
      return decode_ipv4(data.subspan(4));
    }
    case LinkType::user0: {
      if (data.empty() || data[0] > 1) return std::monostate{};
      return SerialChunk{static_cast<protocol::WireDirection>(data[0]), protocol::Bytes(data.begin() + 1, data.end())};
    }
    case LinkType::user1: {
      if (data.empty() || data[0] != 0) return std::monostate{};
      return LptWrites{protocol::Bytes(data.begin() + 1, data.end())};
    }
  }
  return std::monostate{};
}

}  // namespace ldoem::capture
