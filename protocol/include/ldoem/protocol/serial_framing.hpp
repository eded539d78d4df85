// RS-232 / RS-422 framing (spec 4.2): STX, ASCII-hex WORDs, CRC-16 WORD, ETX.
//
// Host -> LD telegram:  STX AAAA LLLL PPPP SSSS [DDDD...] CCCC ETX
//   AAAA address (host 0x00 -> LD 0x10: 0x0010), LLLL = WORDs from LLLL to the last data WORD,
//   PPPP package id 0, SSSS service code, CCCC = serial_crc of every preceding WORD.
// LD -> host reply, split into packages of at most 126 length-counted WORDs:
//   first:        STX AAAA LLLL W2 NNNN payload-words... CCCC ETX   (LLLL = 3 + payload words)
//   continuation: STX AAAA LLLL QQQQ payload-words... CCCC ETX      (LLLL = 2 + payload words)
//   NNNN = number of packages N; QQQQ counts down N-1 ... 1.
// Our choices where the spec says [U] (docs/protocol.md): the LD's address WORD is 0x1000
// (source LD 0x10, destination host 0x00), W2 is 0x0000, every reply carries NNNN (1 for a
// short one), hex is written lowercase (either case is read), and a payload of odd length is
// padded with one 0x00 byte (only GET_IDENTIFICATION text can be odd; its decoder stops at NUL).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/framing.hpp"
#include "ldoem/protocol/profile.hpp"

namespace ldoem::protocol {

inline constexpr std::uint8_t kSerialStx = 0x02;
inline constexpr std::uint8_t kSerialEtx = 0x03;
inline constexpr std::uint16_t kHostToLdAddress = 0x0010;  // S2: source host 0x00, destination LD 0x10
inline constexpr std::uint16_t kLdToHostAddress = 0x1000;  // ours: source LD 0x10, destination host 0x00
inline constexpr std::uint16_t kHostPackageId = 0x0000;    // S2 sends 0 in every host telegram
inline constexpr std::uint16_t kReplyFirstPackageWord2 = 0x0000;  // ours (W2)
// S2 rejects packages whose length WORD exceeds 126.
inline constexpr std::uint16_t kMaxPackageLengthWord = 126;
inline constexpr std::size_t kFirstPackagePayloadWords = kMaxPackageLengthWord - 3;
inline constexpr std::size_t kContinuationPayloadWords = kMaxPackageLengthWord - 2;

// CRC-16 of spec 4.2: polynomial 0x1021, register initialised to 0xFFFF, register-shift form
// `reg = ((reg << 8) | b) ^ TABLE[reg >> 8]`, no reflection, no final XOR.
// serial_crc("123456789") == 0xA69D.
std::uint16_t serial_crc(ByteView bytes);

// Host -> LD telegram (what a host driver sends). An odd payload is padded with 0x00.
// Writes into `out` and returns the size used, or too_large if `out` is too short.
std::size_t serial_request_size(std::size_t payload_size);
base::Expected<std::size_t, DecodeError> encode_serial_request_into(ByteView payload, std::span<std::uint8_t> out,
                                                             std::uint16_t address = kHostToLdAddress);
Bytes encode_serial_request(ByteView payload, std::uint16_t address = kHostToLdAddress);

// LD -> host reply: one telegram per package, in sending order.
std::vector<Bytes> encode_serial_reply_packages(ByteView payload, std::uint16_t address = kLdToHostAddress);
// The packages concatenated, for a single write (D10).
Bytes encode_serial_reply(ByteView payload, std::uint16_t address = kLdToHostAddress);

// One STX ... ETX package, hex decoded to WORDs and CRC-checked: the building block of both
// streaming decoders below. Yields the WORDs before the CRC (address first), or an error.
// Bytes outside STX ... ETX are skipped (counted); an STX inside a package restarts it and
// reports the cut one as truncated; a non-hex character reports bad_hex and waits for the next
// STX; more than max_words WORDs reports too_large. Memory stays below max_words WORDs.
class SerialPackageScanner {
 public:
  struct Package {
    std::vector<std::uint16_t> words;  // address, length, ... (CRC removed)
  };
  struct Error {
    DecodeError detail;
    std::uint16_t service_word;  // the 4th WORD when the package had one (request code), else 0
  };
  using Event = std::variant<Package, Error>;

  explicit SerialPackageScanner(std::size_t max_words);
  std::vector<Event> feed(ByteView chunk);
  std::uint64_t skipped_bytes() const { return skipped_bytes_; }
  bool in_package() const { return state_ != State::hunting; }
  void reset();

 private:
  enum class State { hunting, body };
  void consume(std::uint8_t byte, std::vector<Event>& events);
  void finish(std::vector<Event>& events);
  void fail(DecodeError detail, std::vector<Event>& events);

  std::size_t max_words_;
  State state_ = State::hunting;
  std::vector<std::uint16_t> words_;
  std::uint16_t pending_word_ = 0;
  unsigned pending_digits_ = 0;
  std::uint64_t skipped_bytes_ = 0;
};

// Streaming decoder of host -> LD telegrams (the emulator's side). Each telegram yields a
// Telegram (payload = service WORD + parameters) or a FramingError: bad_hex, bad_crc,
// bad_length (LLLL does not match the WORD count, e.g. S2's GET_CONFIG with LLLL 6),
// truncated, too_large (payload above max_payload), unexpected_frame (package id != 0:
// segmented host telegrams are not supported). Any address WORD is accepted.
class SerialDeframer {
 public:
  explicit SerialDeframer(std::size_t max_payload = kMaxTelegramPayload);
  std::vector<DeframerEvent> feed(ByteView chunk);
  std::uint64_t dropped_frames() const { return dropped_frames_; }
  std::uint64_t skipped_bytes() const { return scanner_.skipped_bytes(); }
  // True while a package has started but is not complete (a caller may time it out, spec 6).
  bool in_frame() const { return scanner_.in_package(); }
  void reset();

 private:
  DeframerEvent interpret(const SerialPackageScanner::Event& event);
  SerialPackageScanner scanner_;
  std::uint64_t dropped_frames_ = 0;
};

// Streaming reassembler of LD -> host replies (the host driver's side). A first package must
// have W2 = 0 and 1 <= NNNN; continuations must count down. Errors: those of the scanner,
// bad_length (LLLL mismatch or a first package without NNNN), bad_sequence (wrong QQQQ or a
// new first package while continuations are due: the partial reply is dropped),
// unexpected_frame (a continuation with no reply in progress), too_large (NNNN or the total
// above what max_payload needs).
class SerialReplyReassembler {
 public:
  explicit SerialReplyReassembler(std::size_t max_payload = kMaxTelegramPayload);
  std::vector<DeframerEvent> feed(ByteView chunk);
  std::uint64_t dropped_frames() const { return dropped_frames_; }
  std::uint64_t skipped_bytes() const { return scanner_.skipped_bytes(); }
  bool in_reply() const { return remaining_packages_ > 0; }
  void reset();

 private:
  void interpret(const SerialPackageScanner::Event& event, std::vector<DeframerEvent>& events);
  void start_reply(const std::vector<std::uint16_t>& words, std::vector<DeframerEvent>& events);
  void continue_reply(const std::vector<std::uint16_t>& words, std::vector<DeframerEvent>& events);
  void drop(FramingError error, std::vector<DeframerEvent>& events);

  std::size_t max_payload_;
  SerialPackageScanner scanner_;
  Bytes payload_;
  std::uint16_t remaining_packages_ = 0;  // continuations still due
  std::uint64_t dropped_frames_ = 0;
};

}  // namespace ldoem::protocol
