// Ethernet/TCP framing (spec 4.1): 02 'U' 'S' 'P' | LENGTH(u32 BE) | payload | XOR(payload).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/framing.hpp"
#include "ldoem/protocol/profile.hpp"

namespace ldoem::protocol {

inline constexpr std::array<std::uint8_t, 4> kTcpMagic{0x02, 0x55, 0x53, 0x50};  // STX "USP"
inline constexpr std::size_t kTcpHeaderSize = 8;                                 // magic + length
inline constexpr std::size_t kTcpTrailerSize = 1;                                // XOR checksum

constexpr std::size_t tcp_frame_size(std::size_t payload_size) {
  return kTcpHeaderSize + payload_size + kTcpTrailerSize;
}
static_assert(tcp_frame_size(kMaxTelegramPayload) == 5825, "spec 4.1: 5825-byte frames");

// XOR of the payload bytes (spec 4.1; 0 for an empty payload).
std::uint8_t xor_checksum(ByteView payload);

// Writes the frame into `out` and returns the number of bytes used, or too_large when `out`
// is shorter than tcp_frame_size(payload.size()). Bytes of `out` past the frame are untouched.
base::Expected<std::size_t, DecodeError> encode_tcp_frame_into(ByteView payload, std::span<std::uint8_t> out);
Bytes encode_tcp_frame(ByteView payload);

// What the deframer does with the bytes of a frame it drops.
enum class TcpResync : std::uint8_t {
  // Hunt on from the byte after the one that showed the error (the emulator's side: a host
  // frame is answered or refused as a whole, D2).
  after_error,
  // Search the dropped frame's own bytes (after its magic) for the next header, so a frame cut
  // short on the wire costs only itself, not the frames that followed it (the driver's side).
  rescan_dropped,
};

// Streaming TCP deframer. Feed bytes in any chunking; each complete frame yields one event, in
// stream order, independent of how the bytes were split.
// - Bytes before a `02 55 53 50` header are skipped (counted in skipped_bytes()).
// - A length above max_payload yields FramingError{too_large} and a bad XOR yields
//   FramingError{bad_checksum, service WORD}; both count in dropped_frames(). With
//   TcpResync::after_error the hunt for the next header starts from the byte after the one that
//   showed the error (payload bytes of an oversized frame are searched as garbage); with
//   rescan_dropped it starts again at the byte after the dropped frame's magic.
// - Memory stays below 2 * (kTcpHeaderSize + max_payload + 1) bytes.
class TcpDeframer {
 public:
  explicit TcpDeframer(std::size_t max_payload = kMaxTelegramPayload, TcpResync resync = TcpResync::after_error);

  std::vector<DeframerEvent> feed(ByteView chunk);

  // Gives up the frame in progress (its sender went quiet, spec 6: S1 aborts a frame after a
  // gap): FramingError{truncated}, counted in dropped_frames(), and its bytes are searched again
  // as rescan_dropped does. Nothing when no frame is in progress.
  std::vector<DeframerEvent> abandon_frame();

  std::uint64_t dropped_frames() const { return dropped_frames_; }
  std::uint64_t skipped_bytes() const { return skipped_bytes_; }
  // True while a frame has started but is not complete (a caller may time it out, spec 6).
  bool in_frame() const { return state_ != State::hunting || magic_matched_ > 0; }
  void reset();

 private:
  enum class State { hunting, length, payload, checksum };
  void consume(std::uint8_t byte, std::vector<DeframerEvent>& events);
  void hunt(std::uint8_t byte);
  void drop(FramingError error, std::vector<DeframerEvent>& events, std::optional<std::uint8_t> last_byte);
  void replay(std::vector<DeframerEvent>& events);

  std::size_t max_payload_;
  TcpResync resync_;
  State state_ = State::hunting;
  std::size_t magic_matched_ = 0;
  std::size_t length_bytes_ = 0;
  std::uint32_t length_ = 0;
  Bytes payload_;
  std::deque<std::uint8_t> replay_;  // bytes of dropped frames still to be searched again
  std::uint64_t dropped_frames_ = 0;
  std::uint64_t skipped_bytes_ = 0;
};

}  // namespace ldoem::protocol
