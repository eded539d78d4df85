#include "ldoem/capture/capture_reader.hpp"

#include <fcntl.h>
#include <pcap/pcap.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <utility>

#include "ldoem/base/regular_file.hpp"

#include "ldoem/capture/candump_log.hpp"
#include "ldoem/capture/pcapng.hpp"

namespace ldoem::capture {

using base::Expected;
using base::Unexpected;

namespace {

// libpcap reports DLT_ values; they equal the LINKTYPE_ values except for raw IP, whose DLT
// differs between platforms.
std::optional<LinkType> link_type_of(int dlt) {
  switch (dlt) {
    case DLT_NULL: return LinkType::null_loopback;
    case DLT_EN10MB: return LinkType::ethernet;
    case DLT_RAW: return LinkType::raw_ip;
    case DLT_LINUX_SLL: return LinkType::linux_sll;
    case DLT_USER0: return LinkType::user0;
    case DLT_USER1: return LinkType::user1;
    case DLT_CAN_SOCKETCAN: return LinkType::can_socketcan;
    case DLT_IPV4: return LinkType::ipv4;
#ifdef DLT_LINUX_SLL2
    case DLT_LINUX_SLL2: return LinkType::linux_sll2;
#endif
    default: return std::nullopt;
  }
}

base::Expected<CapturePackets, std::string> read_with_libpcap(const std::filesystem::path& path, int fd) {
  std::array<char, PCAP_ERRBUF_SIZE> error{};
  // The descriptor already checked to be a regular file; pcap_close closes the FILE.
  const int copy = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
  std::FILE* stream = copy >= 0 ? ::fdopen(copy, "rb") : nullptr;
  if (stream == nullptr) {
    if (copy >= 0) ::close(copy);
    return base::Unexpected(path.string() + ": " + std::strerror(errno));
  }
  std::unique_ptr<pcap_t, decltype(&pcap_close)> handle(
      pcap_fopen_offline_with_tstamp_precision(stream, PCAP_TSTAMP_PRECISION_NANO, error.data()), &pcap_close);
  if (!handle) std::fclose(stream);
  if (!handle) return base::Unexpected(path.string() + ": " + error.data());
  const int dlt = pcap_datalink(handle.get());
  const auto link_type = link_type_of(dlt);
  if (!link_type) {
    const char* name = pcap_datalink_val_to_name(dlt);
    return base::Unexpected(path.string() + ": link type " + (name ? name : std::to_string(dlt)) +
                      " carries no LD-OEM transport (want Ethernet, IPv4, Linux cooked, loopback or SocketCAN)");
  }
  CapturePackets result{CaptureFormat::pcap, {}, {}};
  pcap_pkthdr* header = nullptr;
  const u_char* data = nullptr;
  int status = 0;
  while ((status = pcap_next_ex(handle.get(), &header, &data)) == 1) {
    const auto time = std::chrono::seconds(header->ts.tv_sec) + std::chrono::nanoseconds(header->ts.tv_usec);
    result.packets.push_back(
        {time, decode_link_payload(*link_type, protocol::ByteView(data, header->caplen))});
  }
  if (status == PCAP_ERROR) return base::Unexpected(path.string() + ": " + pcap_geterr(handle.get()));
  return result;
}

// A short read is a failure (the file shrank since fstat, or an I/O error).
bool read_exactly(int fd, std::uintmax_t offset, protocol::Bytes& out) {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t got = ::pread(fd, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    done += static_cast<std::size_t>(got);
  }
  return true;
}

std::uint32_t u32_at(const protocol::Bytes& bytes, std::size_t at, bool big_endian) {
  return big_endian ? (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
                          (std::uint32_t{bytes[at + 2]} << 8) | bytes[at + 3]
                    : (std::uint32_t{bytes[at + 3]} << 24) | (std::uint32_t{bytes[at + 2]} << 16) |
                          (std::uint32_t{bytes[at + 1]} << 8) | bytes[at];
}

// Issue 27: a pcapng file read block by block, so that a bad block is reported as soon as it is
// reached (a 900 MiB file was read whole before "block at byte 11016"), and memory holds the
// decoded packets, not the file. Each packet block is decoded by decode_pcapng together
// with its section's header and interface blocks, which keeps one decoder and its checks.
base::Expected<CapturePackets, std::string> read_pcapng_blocks(const std::filesystem::path& path, int fd,
                                                               std::uintmax_t size) {
  constexpr std::size_t kHeadBytes = 12;  // type, length, and the byte-order magic of a section header
  const auto failed = [&](CaptureFormatError error, std::uintmax_t offset) {
    return base::Unexpected(path.string() + ": block at byte " + std::to_string(offset) + ": " +
                            std::string(describe(error)));
  };
  CapturePackets result{CaptureFormat::pcapng, {}, {}};
  protocol::Bytes section;                                   // this section's header and interface blocks
  std::vector<std::pair<std::size_t, std::uintmax_t>> where;  // their offsets: in `section`, in the file
  bool big_endian = false;
  protocol::Bytes head(kHeadBytes);
  protocol::Bytes block;
  // Issue 27 D9: a recording cut off (a full disk, a crash) keeps its whole blocks; like tshark,
  // read those and say where the file was cut.
  const auto cut_short = [&](std::uintmax_t at) {
    result.warning = path.string() + ": the file ends inside a block at byte " + std::to_string(at) + " (of " +
                     std::to_string(size) + "): it was cut short; read its whole blocks only";
    return result;
  };
  for (std::uintmax_t at = 0; at < size;) {
    if (size - at < kHeadBytes) return at > 0 ? base::Expected<CapturePackets, std::string>(cut_short(at))
                                              : failed(CaptureFormatError::truncated, at);
    if (!read_exactly(fd, at, head)) return failed(CaptureFormatError::truncated, at);
    const bool header = looks_like_pcapng(head);
    if (header) {
      if (u32_at(head, 8, false) == kPcapngByteOrderMagic) {
        big_endian = false;
      } else if (u32_at(head, 8, true) == kPcapngByteOrderMagic) {
        big_endian = true;
      } else {
        return failed(CaptureFormatError::bad_byte_order, at);
      }
    }
    const std::uint32_t type = u32_at(head, 0, big_endian);
    const std::uint32_t length = u32_at(head, 4, big_endian);
    if (length < kHeadBytes || length % 4 != 0 || length > kPcapngMaxBlockBytes) {
      return failed(CaptureFormatError::bad_block_length, at);
    }
    if (length > size - at) return at > 0 ? base::Expected<CapturePackets, std::string>(cut_short(at))
                                          : failed(CaptureFormatError::truncated, at);
    block.resize(length);
    if (!read_exactly(fd, at, block)) return failed(CaptureFormatError::truncated, at);
    if (header) {
      section.clear();
      where.clear();
    }
    const bool keep = header || type == kPcapngInterfaceDescriptionType;
    protocol::Bytes decoded_bytes = keep ? protocol::Bytes{} : section;
    protocol::Bytes& target = keep ? section : decoded_bytes;
    where.emplace_back(target.size(), at);
    target.insert(target.end(), block.begin(), block.end());
    auto packets = decode_pcapng(target);
    if (!packets) {
      std::uintmax_t offset = at;
      for (const auto& [in_section, in_file] : where) {
        if (in_section == packets.error().offset) offset = in_file;
      }
      return failed(packets.error().error, offset);
    }
    if (!keep) where.pop_back();
    if (!keep) {
      for (const auto& packet : *packets) {
        result.packets.push_back({base::SimTime(static_cast<std::int64_t>(packet.time_ns)),
                                  decode_link_payload(packet.link_type, packet.data)});
      }
    }
    at += length;
  }
  return result;
}

}  // namespace

std::string_view format_name(CaptureFormat format) {
  switch (format) {
    case CaptureFormat::pcapng: return "pcapng";
    case CaptureFormat::pcap: return "pcap";
    case CaptureFormat::candump: return "candump log";
  }
  return "?";
}

base::Expected<CapturePackets, std::string> read_capture_packets(const std::filesystem::path& path) {
  // Issue 27: a FIFO, a device or a folder is named as such at once.
  auto opened = base::open_regular_file(path, O_RDONLY);
  if (!opened) return base::Unexpected(path.string() + ": " + opened.error().text);
  struct stat info {};
  if (::fstat(opened->get(), &info) != 0) return base::Unexpected(path.string() + ": " + std::strerror(errno));
  const auto size = static_cast<std::uintmax_t>(info.st_size);
  if (size > kMaxCaptureFileBytes) {
    return base::Unexpected(path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                      std::to_string(kMaxCaptureFileBytes) + " a capture may have (split it with editcap -c)");
  }
  protocol::Bytes magic(4);
  if (!read_exactly(opened->get(), 0, magic)) magic.clear();
  if (looks_like_pcapng(magic)) return read_pcapng_blocks(path, opened->get(), size);
  protocol::Bytes bytes(static_cast<std::size_t>(size));
  if (!read_exactly(opened->get(), 0, bytes)) return base::Unexpected(path.string() + ": cannot read: " + std::strerror(errno));
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (looks_like_candump_log(text)) {
    auto entries = parse_candump_log(text);
    if (!entries) {
      return base::Unexpected(path.string() + ":" + std::to_string(entries.error().line) + ": " +
                        std::string(describe(entries.error().error)));
    }
    CapturePackets result{CaptureFormat::candump, {}, {}};
    for (const auto& entry : *entries) {
      LinkPayload payload = std::monostate{};
      if (!entry.extended_id && !entry.remote) payload = entry.frame;
      result.packets.push_back({base::SimTime(static_cast<std::int64_t>(entry.time_ns)), payload});
    }
    return result;
  }
  return read_with_libpcap(path, opened->get());
}

base::Expected<CaptureConversation, std::string> read_capture_conversation(const std::filesystem::path& path,
                                                                     ConversationConfig config) {
  auto packets = read_capture_packets(path);
  if (!packets) return base::Unexpected(packets.error());
  return CaptureConversation{packets->format, extract_conversation(packets->packets, config),
                             std::move(packets->warning)};
}

}  // namespace ldoem::capture
