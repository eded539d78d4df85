#include "ldoem/capture/capture_reader.hpp"

#include <pcap/pcap.h>

#include <array>
#include <chrono>
#include <optional>
#include <fstream>
#include <iterator>
#include <memory>
#include <system_error>

#include "ldoem/protocol/candump_log.hpp"
#include "ldoem/protocol/pcapng.hpp"

namespace ldoem::capture {

using base::Expected;
using base::Unexpected;

namespace {

// libpcap reports DLT_ values; they equal the LINKTYPE_ values except for raw IP, whose DLT
// differs between platforms.
std::optional<protocol::LinkType> link_type_of(int dlt) {
  switch (dlt) {
    case DLT_NULL: return protocol::LinkType::null_loopback;
    case DLT_EN10MB: return protocol::LinkType::ethernet;
    case DLT_RAW: return protocol::LinkType::raw_ip;
    case DLT_LINUX_SLL: return protocol::LinkType::linux_sll;
    case DLT_USER0: return protocol::LinkType::user0;
    case DLT_USER1: return protocol::LinkType::user1;
    case DLT_CAN_SOCKETCAN: return protocol::LinkType::can_socketcan;
    case DLT_IPV4: return protocol::LinkType::ipv4;
#ifdef DLT_LINUX_SLL2
    case DLT_LINUX_SLL2: return protocol::LinkType::linux_sll2;
#endif
    default: return std::nullopt;
  }
}

base::Expected<CapturePackets, std::string> read_with_libpcap(const std::filesystem::path& path) {
  std::array<char, PCAP_ERRBUF_SIZE> error{};
  std::unique_ptr<pcap_t, decltype(&pcap_close)> handle(
      pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, error.data()), &pcap_close);
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
        {time, protocol::decode_link_payload(*link_type, protocol::ByteView(data, header->caplen))});
  }
  if (status == PCAP_ERROR) return base::Unexpected(path.string() + ": " + pcap_geterr(handle.get()));
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
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) return base::Unexpected(path.string() + ": " + error.message());
  if (size > kMaxCaptureFileBytes) {
    return base::Unexpected(path.string() + ": " + std::to_string(size) + " bytes, more than the " +
                      std::to_string(kMaxCaptureFileBytes) + " a capture may have (split it with editcap -c)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return base::Unexpected(path.string() + ": cannot open for reading");
  const protocol::Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (protocol::looks_like_pcapng(bytes)) {
    auto packets = protocol::decode_pcapng(bytes);
    std::string warning;
    if (!packets && packets.error().error == protocol::CaptureFormatError::truncated && packets.error().offset > 0) {
      // Issue 27 D9: a recording cut off (a full disk, a crash) keeps its whole blocks; like
      // tshark, read those and say where the file was cut.
      const std::size_t whole = packets.error().offset;
      packets = protocol::decode_pcapng(protocol::ByteView(bytes.data(), whole));
      warning = path.string() + ": the file ends inside a block at byte " + std::to_string(whole) + " (of " +
                std::to_string(bytes.size()) + "): it was cut short; read its whole blocks only";
    }
    if (!packets) {
      // One link type only (tcpdump, dumpcap): libpcap reads that too; ours said why it failed.
      return base::Unexpected(path.string() + ": block at byte " + std::to_string(packets.error().offset) + ": " +
                        std::string(protocol::describe(packets.error().error)));
    }
    CapturePackets result{CaptureFormat::pcapng, {}, std::move(warning)};
    result.packets.reserve(packets->size());
    for (const auto& packet : *packets) {
      result.packets.push_back({base::SimTime(static_cast<std::int64_t>(packet.time_ns)),
                                protocol::decode_link_payload(packet.link_type, packet.data)});
    }
    return result;
  }
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (protocol::looks_like_candump_log(text)) {
    auto entries = protocol::parse_candump_log(text);
    if (!entries) {
      return base::Unexpected(path.string() + ":" + std::to_string(entries.error().line) + ": " +
                        std::string(protocol::describe(entries.error().error)));
    }
    CapturePackets result{CaptureFormat::candump, {}, {}};
    for (const auto& entry : *entries) {
      protocol::LinkPayload payload = std::monostate{};
      if (!entry.extended_id && !entry.remote) payload = entry.frame;
      result.packets.push_back({base::SimTime(static_cast<std::int64_t>(entry.time_ns)), payload});
    }
    return result;
  }
  return read_with_libpcap(path);
}

base::Expected<CaptureConversation, std::string> read_capture_conversation(const std::filesystem::path& path,
                                                                     protocol::ConversationConfig config) {
  auto packets = read_capture_packets(path);
  if (!packets) return base::Unexpected(packets.error());
  return CaptureConversation{packets->format, protocol::extract_conversation(packets->packets, config),
                             std::move(packets->warning)};
}

}  // namespace ldoem::capture
