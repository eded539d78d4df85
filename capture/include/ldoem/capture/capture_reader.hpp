// Reads a capture file into packets and telegrams (docs/capture.md). Three formats:
// - pcapng (what `ldoem-emud --record` writes; several link types in one file): decoded by
//   the pure pcapng codec (pcapng.hpp);
// - classic pcap, and pcapng with one link type, as tcpdump and Wireshark write them: read
//   through libpcap (any byte order, micro- or nanosecond stamps);
// - a can-utils `candump -l` log: parsed by the candump codec (candump_log.hpp).
// Files larger than kMaxCaptureFileBytes are refused rather than read into memory.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::capture {

inline constexpr std::uintmax_t kMaxCaptureFileBytes = std::uintmax_t{1} << 30;

enum class CaptureFormat { pcapng, pcap, candump };
std::string_view format_name(CaptureFormat format);

struct CapturePackets {
  CaptureFormat format = CaptureFormat::pcapng;
  std::vector<DecodedPacket> packets;
  // Not empty when the file was read only in part: a pcapng cut inside a block (a full disk,
  // a crash) gives its whole blocks and says so here.
  std::string warning;
};

// Every packet of the file, decoded per link type, with its time. Errors name the file and
// what was wrong ("capture.pcapng: block at byte 1234: file ends inside a block").
[[nodiscard]] base::Expected<CapturePackets, std::string> read_capture_packets(const std::filesystem::path& path);

struct CaptureConversation {
  CaptureFormat format = CaptureFormat::pcapng;
  Conversation conversation;
  std::string warning;  // as CapturePackets::warning
};

// The telegrams of the file (extract_conversation), in capture order.
[[nodiscard]] base::Expected<CaptureConversation, std::string> read_capture_conversation(
    const std::filesystem::path& path, ConversationConfig config = {});

}  // namespace ldoem::capture
