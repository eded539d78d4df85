// What one captured packet carries, per link type, as pure codecs (docs/capture.md):
// - CAN: a SocketCAN frame as LINKTYPE_CAN_SOCKETCAN stores it (8-byte header, CAN id
//   big-endian, then the data bytes);
// - TCP: an IPv4/TCP packet, synthesized by ldoem's recorder (so Wireshark's TCP reassembly
//   works) or taken from a real capture behind Ethernet, Linux cooked, loopback or raw-IP
//   headers;
// - serial: LINKTYPE_USER0, one direction byte (0 host to device, 1 device to host) then the
//   bytes as they crossed the line;
// - LPT: LINKTYPE_USER1, one direction byte (always 0) then the data-register values written.
#pragma once

#include <cstdint>
#include <optional>
#include <variant>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/can_frame.hpp"
#include "ldoem/capture/pcapng.hpp"
#include "ldoem/protocol/wire_direction.hpp"

namespace ldoem::capture {

inline constexpr std::size_t kSocketCanHeaderBytes = 8;
inline constexpr std::uint32_t kSocketCanExtendedFlag = 0x80000000;
inline constexpr std::uint32_t kSocketCanRemoteFlag = 0x40000000;
inline constexpr std::uint32_t kSocketCanErrorFlag = 0x20000000;

protocol::Bytes encode_socketcan_packet(const protocol::CanFrame& frame);

struct TcpSegment {
  std::uint32_t source_ip = 0;  // host byte order
  std::uint32_t destination_ip = 0;
  std::uint16_t source_port = 0;
  std::uint16_t destination_port = 0;
  std::uint32_t sequence = 0;
  std::uint32_t acknowledgement = 0;
  std::uint8_t flags = 0;  // TCP flag bits, kTcpSyn etc.
  protocol::Bytes payload;
  bool operator==(const TcpSegment&) const = default;
};
inline constexpr std::uint8_t kTcpFin = 0x01;
inline constexpr std::uint8_t kTcpSyn = 0x02;
inline constexpr std::uint8_t kTcpRst = 0x04;
inline constexpr std::uint8_t kTcpPsh = 0x08;
inline constexpr std::uint8_t kTcpAck = 0x10;

// An IPv4 packet (20-byte header, no options, DF set, TTL 64) holding one TCP segment (20-byte
// header, window 65535), both checksums computed. Payloads above 65495 bytes do not fit one
// IPv4 packet: the caller splits them (the recorder uses segments of at most 1460 bytes).
protocol::Bytes encode_ipv4_tcp_packet(const TcpSegment& segment);

struct SerialChunk {
  protocol::WireDirection direction = protocol::WireDirection::host_to_device;
  protocol::Bytes bytes;
  bool operator==(const SerialChunk&) const = default;
};
struct LptWrites {
  protocol::Bytes values;  // data-register values in write order (D8)
  bool operator==(const LptWrites&) const = default;
};

protocol::Bytes encode_serial_packet(const SerialChunk& chunk);
protocol::Bytes encode_lpt_packet(const LptWrites& writes);

// What a packet turned out to be. Anything else (IPv6, UDP, ARP, IP fragments, error or remote
// CAN frames, extended CAN ids, CAN FD, unknown link types) is `std::monostate` and ignored by
// the conversation extractor.
using LinkPayload = std::variant<std::monostate, protocol::CanFrame, TcpSegment, SerialChunk, LptWrites>;

LinkPayload decode_link_payload(LinkType link_type, protocol::ByteView data);

}  // namespace ldoem::capture
