// libFuzzer: the capture reader's pure part (docs/capture.md) on arbitrary bytes: the pcapng
// decoder, every link-type payload decoder and the conversation extractor behind them. Errors
// must be typed values; a decoded packet never holds more bytes than the file; re-encoding a
// packet and decoding it again gives the same packet.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/capture/pcapng.hpp"

using namespace ldoem::protocol;
using namespace ldoem::capture;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ByteView input(data, size);
  // Every link decoder on the raw bytes, whatever they are.
  for (const auto link : {LinkType::null_loopback, LinkType::ethernet, LinkType::raw_ip, LinkType::linux_sll,
                          LinkType::user0, LinkType::user1, LinkType::can_socketcan, LinkType::ipv4,
                          LinkType::linux_sll2}) {
    const LinkPayload payload = decode_link_payload(link, input);
    if (const auto* segment = std::get_if<TcpSegment>(&payload); segment && segment->payload.size() > size) std::abort();
  }
  const auto packets = decode_pcapng(input);
  if (!packets) {
    if (packets.error().offset >= size && size > 0) std::abort();
    return 0;
  }
  std::vector<DecodedPacket> decoded;
  for (const auto& packet : *packets) {
    if (packet.data.size() > size) std::abort();
    const Bytes block = encode_pcapng_packet(0, packet.time_ns, packet.data, packet.direction);
    Bytes file = encode_pcapng_section_header("");
    const Bytes interface = encode_pcapng_interface(packet.link_type, "");
    file.insert(file.end(), interface.begin(), interface.end());
    file.insert(file.end(), block.begin(), block.end());
    const auto again = decode_pcapng(file);
    if (!again || again->size() != 1 || (*again)[0].data != packet.data || (*again)[0].time_ns != packet.time_ns ||
        (*again)[0].direction != packet.direction) {
      std::abort();
    }
    decoded.push_back({ldoem::base::SimTime(static_cast<std::int64_t>(packet.time_ns & 0x3FFFFFFFFFFFFFFF)),
                       decode_link_payload(packet.link_type, packet.data)});
  }
  const Conversation conversation = extract_conversation(decoded);
  for (const auto& telegram : conversation.telegrams) {
    // An empty payload is a valid frame (TCP length 0); the bound is the largest reassembly.
    if (telegram.payload.size() > kIsoTpDefaultMaxMessageBytes) std::abort();
  }
  return 0;
}
