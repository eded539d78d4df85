// libFuzzer: the serial host-telegram deframer and the LD reply reassembler (spec 4.2) on
// arbitrary bytes. Chunking must not change the events; errors must be from the listed set.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ldoem/protocol/serial_framing.hpp"

using namespace ldoem::protocol;

namespace {

template <class Decoder>
void check_chunking(ByteView input, std::size_t chunk, std::size_t max_payload) {
  Decoder whole(max_payload);
  const auto events = whole.feed(input);
  Decoder chunked(max_payload);
  std::vector<DeframerEvent> chunked_events;
  for (std::size_t i = 0; i < input.size(); i += chunk) {
    for (auto& event : chunked.feed(input.subspan(i, std::min(chunk, input.size() - i)))) {
      chunked_events.push_back(std::move(event));
    }
  }
  if (events != chunked_events) std::abort();
  for (const auto& event : events) {
    if (const auto* telegram = std::get_if<Telegram>(&event)) {
      if (telegram->payload.size() > max_payload + 1) std::abort();  // +1: odd padding
      continue;
    }
    switch (std::get<FramingError>(event).detail) {
      case DecodeError::truncated: case DecodeError::bad_length: case DecodeError::bad_hex:
      case DecodeError::bad_crc: case DecodeError::too_large: case DecodeError::bad_sequence:
      case DecodeError::unexpected_frame:
        break;
      default:
        std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 7;
  const std::size_t max_payload = (data[0] & 0x80) ? 8 : kMaxTelegramPayload;
  const ByteView input(data + 1, size - 1);
  check_chunking<SerialDeframer>(input, chunk, max_payload);
  check_chunking<SerialReplyReassembler>(input, chunk, max_payload);
  // Every telegram the encoder makes comes back through the deframer.
  SerialDeframer deframer;
  const auto events = deframer.feed(encode_serial_request(input.first(std::min<std::size_t>(input.size(), 64) & ~std::size_t{1})));
  if (events.size() != 1 || !std::holds_alternative<Telegram>(events[0])) std::abort();
  return 0;
}
