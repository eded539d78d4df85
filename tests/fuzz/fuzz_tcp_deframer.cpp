// libFuzzer: the TCP deframer (spec 4.1) on arbitrary bytes. Whole and byte-by-byte feeding must
// give the same events, and no telegram may exceed the configured maximum.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ldoem/protocol/tcp_framing.hpp"

using namespace ldoem::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ByteView input(data, size);
  // A small maximum makes the too_large path reachable with short inputs.
  const std::size_t max_payload = size > 0 && (data[0] & 1) ? 16 : kMaxTelegramPayload;
  TcpDeframer whole(max_payload);
  const auto events = whole.feed(input);
  TcpDeframer bytewise(max_payload);
  std::vector<DeframerEvent> bytewise_events;
  for (std::size_t i = 0; i < size; ++i) {
    for (auto& event : bytewise.feed(input.subspan(i, 1))) bytewise_events.push_back(std::move(event));
  }
  if (events != bytewise_events) std::abort();
  for (const auto& event : events) {
    if (const auto* telegram = std::get_if<Telegram>(&event)) {
      if (telegram->payload.size() > max_payload) std::abort();
      // A delivered payload framed again is what the stream carried.
      (void)encode_tcp_frame(telegram->payload);
    } else {
      const auto detail = std::get<FramingError>(event).detail;
      if (detail != DecodeError::bad_checksum && detail != DecodeError::too_large) std::abort();
    }
  }
  return 0;
}
