// libFuzzer: the TCP deframer (spec 4.1) on arbitrary bytes, in both resync modes (the second
// input bit picks rescan_dropped, the driver's). Whole and byte-by-byte feeding must give the
// same events, no telegram may exceed the configured maximum, and abandon_frame() at the end
// gives a frame in progress up
// within a bounded number of rounds.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ldoem/protocol/tcp_framing.hpp"

using namespace ldoem::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ByteView input(data, size);
  // A small maximum makes the too_large path reachable with short inputs.
  const std::size_t max_payload = size > 0 && (data[0] & 1) ? 16 : kMaxTelegramPayload;
  const TcpResync resync = size > 0 && (data[0] & 2) ? TcpResync::rescan_dropped : TcpResync::after_error;
  TcpDeframer whole(max_payload, resync);
  const auto events = whole.feed(input);
  TcpDeframer bytewise(max_payload, resync);
  std::vector<DeframerEvent> bytewise_events;
  for (std::size_t i = 0; i < size; ++i) {
    for (auto& event : bytewise.feed(input.subspan(i, 1))) bytewise_events.push_back(std::move(event));
  }
  if (events != bytewise_events) std::abort();
  auto all = events;
  // Each abandon gives up at least a magic's worth of bytes, so a frame nested in an abandoned
  // one is given up in turn within size / 4 + 1 rounds.
  for (std::size_t round = 0; whole.in_frame() && round <= size / 4 + 1; ++round) {
    for (auto& event : whole.abandon_frame()) all.push_back(std::move(event));
  }
  if (whole.in_frame()) std::abort();
  for (const auto& event : all) {
    if (const auto* telegram = std::get_if<Telegram>(&event)) {
      if (telegram->payload.size() > max_payload) std::abort();
      // A delivered payload framed again is what the stream carried.
      (void)encode_tcp_frame(telegram->payload);
    } else {
      const auto detail = std::get<FramingError>(event).detail;
      if (detail != DecodeError::bad_checksum && detail != DecodeError::too_large && detail != DecodeError::truncated) {
        std::abort();
      }
    }
  }
  return 0;
}
