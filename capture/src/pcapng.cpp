#include "ldoem/capture/pcapng.hpp"

#include <array>

namespace ldoem::capture {
namespace {

constexpr std::uint16_t kOptEndOfOpt = 0;
constexpr std::uint16_t kOptShbUserAppl = 4;
constexpr std::uint16_t kOptIfName = 2;
constexpr std::uint16_t kOptIfTsresol = 9;
constexpr std::uint16_t kOptEpbFlags = 2;
constexpr std::uint8_t kNanosecondResolution = 9;
constexpr std::size_t kBlockOverhead = 12;  // type, length, trailing length

void put_u16(protocol::Bytes& out, std::uint16_t value) {
  out.push_back(static_cast<std::uint8_t>(value & 0xFF));
  out.push_back(static_cast<std::uint8_t>(value >> 8));
}

void put_u32(protocol::Bytes& out, std::uint32_t value) {
  put_u16(out, static_cast<std::uint16_t>(value & 0xFFFF));
  put_u16(out, static_cast<std::uint16_t>(value >> 16));
}

void pad_to_4(protocol::Bytes& out) {
  while (out.size() % 4 != 0) out.push_back(0);
}

void put_option(protocol::Bytes& out, std::uint16_t code, protocol::ByteView value) {
  put_u16(out, code);
  put_u16(out, static_cast<std::uint16_t>(value.size()));
  out.insert(out.end(), value.begin(), value.end());
  pad_to_4(out);
}

protocol::ByteView text_bytes(std::string_view text) {
  return protocol::ByteView(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

// Wraps a block body in type, total length and trailing total length.
protocol::Bytes make_block(std::uint32_t type, const protocol::Bytes& body) {
  const auto total = static_cast<std::uint32_t>(body.size() + kBlockOverhead);
  protocol::Bytes block;
  block.reserve(total);
  put_u32(block, type);
  put_u32(block, total);
  block.insert(block.end(), body.begin(), body.end());
  put_u32(block, total);
  return block;
}

// Reads integers in the byte order the current section declared.
struct SectionReader {
  protocol::ByteView bytes;
  bool big_endian = false;

  std::uint16_t u16(std::size_t at) const {
    return big_endian ? static_cast<std::uint16_t>((bytes[at] << 8) | bytes[at + 1])
                      : static_cast<std::uint16_t>(bytes[at] | (bytes[at + 1] << 8));
  }
  std::uint32_t u32(std::size_t at) const {
    const std::uint32_t a = u16(at);
    const std::uint32_t b = u16(at + 2);
    return big_endian ? (a << 16) | b : (b << 16) | a;
  }
};

struct Interface {
  LinkType link_type;
  // Timestamp units per second, and whether the unit is a power of 2 rather than of 10.
  std::uint8_t resolution_exponent = 6;
  bool binary_resolution = false;
};

std::uint64_t to_nanoseconds(const Interface& interface, std::uint64_t ticks) {
  if (interface.binary_resolution) {
    const unsigned shift = interface.resolution_exponent;
    if (shift >= 64) return 0;
    const std::uint64_t seconds = ticks >> shift;
    const std::uint64_t fraction = ticks & ((std::uint64_t{1} << shift) - 1);
    const auto fraction_ns = static_cast<std::uint64_t>(
        (static_cast<unsigned __int128>(fraction) * 1'000'000'000u) >> shift);
    return seconds * 1'000'000'000ull + fraction_ns;
  }
  unsigned exponent = interface.resolution_exponent;
  if (exponent <= 9) {
    std::uint64_t scale = 1;
    for (unsigned i = exponent; i < 9; ++i) scale *= 10;
    return ticks * scale;
  }
  for (; exponent > 9 && ticks > 0; --exponent) ticks /= 10;
  return ticks;
}

// Options of an IDB: only if_tsresol matters for reading.
void read_interface_options(const SectionReader& reader, std::size_t at, std::size_t end, Interface& interface) {
  while (at + 4 <= end) {
    const std::uint16_t code = reader.u16(at);
    const std::uint16_t length = reader.u16(at + 2);
    const std::size_t value = at + 4;
    if (code == kOptEndOfOpt || value + length > end) return;
    if (code == kOptIfTsresol && length >= 1) {
      const std::uint8_t raw = reader.bytes[value];
      interface.binary_resolution = (raw & 0x80) != 0;
      interface.resolution_exponent = raw & 0x7F;
    }
    at = value + ((length + 3u) & ~std::size_t{3});
  }
}

PacketDirection read_packet_flags(const SectionReader& reader, std::size_t at, std::size_t end) {
  while (at + 4 <= end) {
    const std::uint16_t code = reader.u16(at);
    const std::uint16_t length = reader.u16(at + 2);
    const std::size_t value = at + 4;
    if (code == kOptEndOfOpt || value + length > end) break;
    if (code == kOptEpbFlags && length == 4) {
      switch (reader.u32(value) & 0x3) {
        case 1: return PacketDirection::inbound;
        case 2: return PacketDirection::outbound;
        default: return PacketDirection::unknown;
      }
    }
    at = value + ((length + 3u) & ~std::size_t{3});
  }
  return PacketDirection::unknown;
}

}  // namespace

std::string_view describe(CaptureFormatError error) {
  switch (error) {
    case CaptureFormatError::not_pcapng: return "not a pcapng file (no section header block first)";
    case CaptureFormatError::bad_byte_order: return "section header with an unknown byte-order magic";
    case CaptureFormatError::bad_block_length: return "block length below 12, unaligned, or past the end";
    case CaptureFormatError::truncated: return "file ends inside a block";
    case CaptureFormatError::bad_packet_length: return "packet length larger than its block";
    case CaptureFormatError::unknown_interface: return "packet names an interface no description block declared";
  }
  return "unknown capture format error";
}

protocol::Bytes encode_pcapng_section_header(std::string_view application) {
  protocol::Bytes body;
  put_u32(body, kPcapngByteOrderMagic);
  put_u16(body, 1);
  put_u16(body, 0);
  put_u32(body, 0xFFFFFFFF);  // section length unknown (-1), so a file can grow and be cut
  put_u32(body, 0xFFFFFFFF);
  if (!application.empty()) put_option(body, kOptShbUserAppl, text_bytes(application));
  put_option(body, kOptEndOfOpt, {});
  return make_block(kPcapngSectionHeaderType, body);
}

protocol::Bytes encode_pcapng_interface(LinkType link_type, std::string_view name) {
  protocol::Bytes body;
  put_u16(body, static_cast<std::uint16_t>(link_type));
  put_u16(body, 0);
  put_u32(body, kCaptureSnapLength);
  if (!name.empty()) put_option(body, kOptIfName, text_bytes(name));
  const std::array<std::uint8_t, 1> resolution{kNanosecondResolution};
  put_option(body, kOptIfTsresol, resolution);
  put_option(body, kOptEndOfOpt, {});
  return make_block(kPcapngInterfaceDescriptionType, body);
}

protocol::Bytes encode_pcapng_packet(std::uint32_t interface_id, std::uint64_t time_ns, protocol::ByteView data,
                           PacketDirection direction) {
  protocol::Bytes body;
  body.reserve(data.size() + 40);
  put_u32(body, interface_id);
  put_u32(body, static_cast<std::uint32_t>(time_ns >> 32));
  put_u32(body, static_cast<std::uint32_t>(time_ns & 0xFFFFFFFF));
  put_u32(body, static_cast<std::uint32_t>(data.size()));
  put_u32(body, static_cast<std::uint32_t>(data.size()));
  body.insert(body.end(), data.begin(), data.end());
  pad_to_4(body);
  if (direction != PacketDirection::unknown) {
    protocol::Bytes flags;
    put_u32(flags, static_cast<std::uint32_t>(direction));
    put_option(body, kOptEpbFlags, flags);
    put_option(body, kOptEndOfOpt, {});
  }
  return make_block(kPcapngEnhancedPacketType, body);
}

bool looks_like_pcapng(protocol::ByteView file) {
  return file.size() >= 4 && file[0] == 0x0A && file[1] == 0x0D && file[2] == 0x0D && file[3] == 0x0A;
}

base::Expected<std::vector<CapturePacket>, CaptureFormatFailure> decode_pcapng(protocol::ByteView file) {
  const auto fail = [](CaptureFormatError error, std::size_t offset) {
    return base::Unexpected(CaptureFormatFailure{error, offset});
  };
  if (!looks_like_pcapng(file)) return fail(CaptureFormatError::not_pcapng, 0);
  std::vector<CapturePacket> packets;
  std::vector<Interface> interfaces;
  SectionReader reader{file, false};
  std::size_t at = 0;
  while (at < file.size()) {
    if (file.size() - at < kBlockOverhead) return fail(CaptureFormatError::truncated, at);
    const bool section = file[at] == 0x0A && file[at + 1] == 0x0D && file[at + 2] == 0x0D && file[at + 3] == 0x0A;
    if (section) {
      if (file.size() - at < 16) return fail(CaptureFormatError::truncated, at);
      const std::uint32_t magic_le = SectionReader{file, false}.u32(at + 8);
      if (magic_le == kPcapngByteOrderMagic) {
        reader.big_endian = false;
      } else if (SectionReader{file, true}.u32(at + 8) == kPcapngByteOrderMagic) {
        reader.big_endian = true;
      } else {
        return fail(CaptureFormatError::bad_byte_order, at);
      }
      interfaces.clear();
    }
    const std::uint32_t type = reader.u32(at);
    const std::uint32_t length = reader.u32(at + 4);
    if (length < kBlockOverhead || length % 4 != 0 || length > kPcapngMaxBlockBytes) {
      return fail(CaptureFormatError::bad_block_length, at);
    }
    if (length > file.size() - at) return fail(CaptureFormatError::truncated, at);
    if (reader.u32(at + length - 4) != length) return fail(CaptureFormatError::bad_block_length, at);
    const std::size_t body = at + 8;
    const std::size_t end = at + length - 4;
    if (type == kPcapngInterfaceDescriptionType) {
      if (end - body < 8) return fail(CaptureFormatError::bad_block_length, at);
      Interface interface{static_cast<LinkType>(reader.u16(body))};
      read_interface_options(reader, body + 8, end, interface);
      interfaces.push_back(interface);
    } else if (type == kPcapngEnhancedPacketType || type == kPcapngObsoletePacketType) {
      if (end - body < 20) return fail(CaptureFormatError::bad_block_length, at);
      const std::uint32_t interface_id = type == kPcapngEnhancedPacketType ? reader.u32(body) : reader.u16(body);
      if (interface_id >= interfaces.size()) return fail(CaptureFormatError::unknown_interface, at);
      const std::uint64_t ticks = (std::uint64_t{reader.u32(body + 4)} << 32) | reader.u32(body + 8);
      const std::uint32_t captured = reader.u32(body + 12);
      const std::size_t data = body + 20;
      if (captured > end - data) return fail(CaptureFormatError::bad_packet_length, at);
      CapturePacket packet;
      packet.link_type = interfaces[interface_id].link_type;
      packet.interface_id = interface_id;
      packet.time_ns = to_nanoseconds(interfaces[interface_id], ticks);
      packet.data.assign(file.begin() + static_cast<std::ptrdiff_t>(data),
                         file.begin() + static_cast<std::ptrdiff_t>(data + captured));
      if (type == kPcapngEnhancedPacketType) {
        packet.direction = read_packet_flags(reader, data + ((captured + 3u) & ~std::size_t{3}), end);
      }
      packets.push_back(std::move(packet));
    } else if (type == kPcapngSimplePacketType) {
      if (end - body < 4) return fail(CaptureFormatError::bad_block_length, at);
      if (interfaces.empty()) return fail(CaptureFormatError::unknown_interface, at);
      const std::uint32_t original = reader.u32(body);
      const std::size_t available = end - (body + 4);
      const std::size_t captured = original < available ? original : available;
      CapturePacket packet;
      packet.link_type = interfaces[0].link_type;
      packet.data.assign(file.begin() + static_cast<std::ptrdiff_t>(body + 4),
                         file.begin() + static_cast<std::ptrdiff_t>(body + 4 + captured));
      packets.push_back(std::move(packet));
    }
    at += length;
  }
  return packets;
}

}  // namespace ldoem::capture
