// pcapng blocks (the IETF draft "PCAP Next Generation Dump File Format"), as pure codecs: the
// capture writer (capture_writer.hpp) puts these bytes in a file, the capture reader decodes a file's
// bytes. No I/O here. docs/capture.md says which link types ldoem writes and why.
//
// What we write (always little-endian, one section):
//   SHB  0A0D0D0A | len | 1A2B3C4D | 1.0 | section length -1 | opt shb_userappl | len
//   IDB  00000001 | len | linktype(16) 0 | snaplen | opt if_name, if_tsresol = 9 (ns) | len
//   EPB  00000006 | len | interface | ts high | ts low | caplen | origlen | data, padded to 4
//        | opt epb_flags (direction: 1 inbound = host to device, 2 outbound) | len
// What we read: SHB of either byte order, IDB (link type, if_tsresol), EPB, SPB and the
// obsolete PB; other block types are skipped. Every length is checked against the bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::capture {

// Link-layer header types (tcpdump.org's LINKTYPE_ registry) that ldoem reads or writes.
enum class LinkType : std::uint16_t {
  null_loopback = 0,    // BSD loopback: 4-byte address family, then IP
  ethernet = 1,
  raw_ip = 101,         // raw IPv4 or IPv6
  linux_sll = 113,      // Linux cooked capture v1 (tcpdump -i any)
  user0 = 147,          // ours: serial bytes (docs/capture.md)
  user1 = 148,          // ours: LPT data-register writes (docs/capture.md)
  can_socketcan = 227,  // SocketCAN frames, CAN id big-endian
  ipv4 = 228,
  linux_sll2 = 276,
};

inline constexpr std::uint32_t kPcapngSectionHeaderType = 0x0A0D0D0A;
inline constexpr std::uint32_t kPcapngByteOrderMagic = 0x1A2B3C4D;
inline constexpr std::uint32_t kPcapngInterfaceDescriptionType = 0x00000001;
inline constexpr std::uint32_t kPcapngObsoletePacketType = 0x00000002;
inline constexpr std::uint32_t kPcapngSimplePacketType = 0x00000003;
inline constexpr std::uint32_t kPcapngEnhancedPacketType = 0x00000006;
// A block larger than this is refused when reading: no ldoem packet comes near it, and it keeps
// a hostile length from reserving memory.
inline constexpr std::size_t kPcapngMaxBlockBytes = 16u << 20;
inline constexpr std::uint32_t kCaptureSnapLength = 262144;

// pcapng's epb_flags direction bits, seen from the device: a request comes in.
enum class PacketDirection : std::uint8_t { unknown = 0, inbound = 1, outbound = 2 };

protocol::Bytes encode_pcapng_section_header(std::string_view application);
protocol::Bytes encode_pcapng_interface(LinkType link_type, std::string_view name);
// time_ns: nanoseconds since the epoch of the capture (ldoem: device time, docs/capture.md).
protocol::Bytes encode_pcapng_packet(std::uint32_t interface_id, std::uint64_t time_ns, protocol::ByteView data,
                           PacketDirection direction);

enum class CaptureFormatError : std::uint8_t {
  not_pcapng,           // the first block is not a section header
  bad_byte_order,       // section header with an unknown byte-order magic
  bad_block_length,     // length below 12, not a multiple of 4, past the end or over the cap
  truncated,            // the file ends inside a block
  bad_packet_length,    // captured length larger than the block holds
  unknown_interface,    // a packet names an interface no IDB described
};
std::string_view describe(CaptureFormatError error);

struct CaptureFormatFailure {
  CaptureFormatError error = CaptureFormatError::truncated;
  std::size_t offset = 0;  // byte offset of the block that failed
};

// One packet of a capture, whatever the file format was.
struct CapturePacket {
  LinkType link_type = LinkType::ethernet;
  std::uint32_t interface_id = 0;
  std::uint64_t time_ns = 0;
  PacketDirection direction = PacketDirection::unknown;
  protocol::Bytes data;
  bool operator==(const CapturePacket&) const = default;
};

// Every packet of a pcapng file's bytes, in file order. A later section header starts a new
// set of interfaces (interface ids are per section).
[[nodiscard]] base::Expected<std::vector<CapturePacket>, CaptureFormatFailure> decode_pcapng(protocol::ByteView file);

// True when the bytes start with a pcapng section header type.
bool looks_like_pcapng(protocol::ByteView file);

}  // namespace ldoem::capture
