// RS-232 / RS-422 framing (spec 4.2) and our choices for the LD -> host side (docs/protocol.md).
#include "ldoem/protocol/serial_framing.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <string_view>

namespace ldoem::protocol {
namespace {

constexpr std::uint16_t kCrcPolynomial = 0x1021;  // x^16 + x^12 + x^5 + 1
constexpr std::uint16_t kCrcInitial = 0xFFFF;

// The MSB-first CCITT table: TABLE[i] = i * x^16 mod P, as spec 4.2 describes.
constexpr std::array<std::uint16_t, 256> make_crc_table() {
  std::array<std::uint16_t, 256> table{};
  for (unsigned index = 0; index < 256; ++index) {
    unsigned reg = index << 8;
    for (int bit = 0; bit < 8; ++bit) reg = (reg & 0x8000) ? ((reg << 1) ^ kCrcPolynomial) : (reg << 1);
    table[index] = static_cast<std::uint16_t>(reg);
  }
  return table;
}
constexpr auto kCrcTable = make_crc_table();
static_assert(kCrcTable[0xFF] == 0x1EF0 && kCrcTable[0xE1] == 0xED0F, "spec 4.2 worked example");

constexpr std::string_view kLowerHex = "0123456789abcdef";
constexpr std::size_t kHexDigitsPerWord = 4;

std::size_t words_for(std::size_t payload_size) { return (payload_size + 1) / 2; }

// The payload as WORDs, an odd last byte padded with 0x00 (our choice, see the header).
std::uint16_t payload_word(ByteView payload, std::size_t index) {
  const std::size_t offset = 2 * index;
  const std::uint8_t low = offset + 1 < payload.size() ? payload[offset + 1] : std::uint8_t{0};
  return static_cast<std::uint16_t>((payload[offset] << 8) | low);
}

// Accumulates WORDs as hex digits and their CRC.
class PackageWriter {
 public:
  explicit PackageWriter(std::uint8_t* out) : cursor_(out) { *cursor_++ = kSerialStx; }
  void word(std::uint16_t value) {
    crc_ = crc_step(crc_, static_cast<std::uint8_t>(value >> 8));
    crc_ = crc_step(crc_, static_cast<std::uint8_t>(value & 0xFF));
    write_hex(value);
  }
  std::uint8_t* finish() {
    write_hex(crc_);
    *cursor_++ = kSerialEtx;
    return cursor_;
  }
  static std::uint16_t crc_step(std::uint16_t reg, std::uint8_t byte) {
    return static_cast<std::uint16_t>(((reg << 8) | byte) ^ kCrcTable[reg >> 8]);
  }

 private:
  void write_hex(std::uint16_t value) {
    for (int shift = 12; shift >= 0; shift -= 4) *cursor_++ = static_cast<std::uint8_t>(kLowerHex[(value >> shift) & 0xF]);
  }
  std::uint8_t* cursor_;
  std::uint16_t crc_ = kCrcInitial;
};

constexpr std::size_t package_size(std::size_t words_before_crc) {
  return 2 + kHexDigitsPerWord * (words_before_crc + 1);
}

std::optional<std::uint8_t> hex_value(std::uint8_t character) {
  if (character >= '0' && character <= '9') return static_cast<std::uint8_t>(character - '0');
  if (character >= 'a' && character <= 'f') return static_cast<std::uint8_t>(character - 'a' + 10);
  if (character >= 'A' && character <= 'F') return static_cast<std::uint8_t>(character - 'A' + 10);
  return std::nullopt;
}

Bytes words_to_bytes(const std::vector<std::uint16_t>& words, std::size_t first) {
  Bytes bytes;
  bytes.reserve(2 * (words.size() - first));
  for (std::size_t i = first; i < words.size(); ++i) append_word_be(bytes, words[i]);
  return bytes;
}

std::size_t max_reply_packages(std::size_t max_payload) {
  const std::size_t words = words_for(max_payload);
  if (words <= kFirstPackagePayloadWords) return 1;
  return 1 + (words - kFirstPackagePayloadWords + kContinuationPayloadWords - 1) / kContinuationPayloadWords;
}

}  // namespace

std::uint16_t serial_crc(ByteView bytes) {
  std::uint16_t reg = kCrcInitial;
  for (const auto byte : bytes) reg = PackageWriter::crc_step(reg, byte);
  return reg;
}

// -------------------------------------------------------------------------- host -> LD

std::size_t serial_request_size(std::size_t payload_size) {
  return package_size(3 + words_for(payload_size));  // address, length, package id
}

base::Expected<std::size_t, DecodeError> encode_serial_request_into(ByteView payload, std::span<std::uint8_t> out,
                                                             std::uint16_t address) {
  const std::size_t size = serial_request_size(payload.size());
  const std::size_t payload_words = words_for(payload.size());
  if (out.size() < size || payload_words + 2 > UINT16_MAX) return base::Unexpected(DecodeError::too_large);
  PackageWriter writer(out.data());
  writer.word(address);
  writer.word(static_cast<std::uint16_t>(2 + payload_words));  // LLLL counts itself and PPPP
  writer.word(kHostPackageId);
  for (std::size_t i = 0; i < payload_words; ++i) writer.word(payload_word(payload, i));
  writer.finish();
  return size;
}

Bytes encode_serial_request(ByteView payload, std::uint16_t address) {
  Bytes out(serial_request_size(payload.size()));
  const auto used = encode_serial_request_into(payload, out, address);
  out.resize(used.value_or(0));
  return out;
}

// -------------------------------------------------------------------------- LD -> host

std::vector<Bytes> encode_serial_reply_packages(ByteView payload, std::uint16_t address) {
  const std::size_t payload_words = words_for(payload.size());
  const std::size_t package_count = max_reply_packages(payload.size());
  std::vector<Bytes> packages;
  packages.reserve(package_count);
  std::size_t next_word = 0;
  for (std::size_t package = 0; package < package_count; ++package) {
    const bool first = package == 0;
    const std::size_t capacity = first ? kFirstPackagePayloadWords : kContinuationPayloadWords;
    const std::size_t words = std::min(capacity, payload_words - next_word);
    const std::size_t header_words = first ? 4 : 3;  // address, LLLL, W2, NNNN | address, LLLL, QQQQ
    Bytes bytes(package_size(header_words + words));
    PackageWriter writer(bytes.data());
    writer.word(address);
    writer.word(static_cast<std::uint16_t>(header_words - 1 + words));
    if (first) {
      writer.word(kReplyFirstPackageWord2);
      writer.word(static_cast<std::uint16_t>(package_count));
    } else {
      writer.word(static_cast<std::uint16_t>(package_count - package));  // N-1 ... 1
    }
    for (std::size_t i = 0; i < words; ++i) writer.word(payload_word(payload, next_word + i));
    next_word += words;
    writer.finish();
    packages.push_back(std::move(bytes));
  }
  return packages;
}

Bytes encode_serial_reply(ByteView payload, std::uint16_t address) {
  Bytes out;
  for (const auto& package : encode_serial_reply_packages(payload, address)) {
    out.insert(out.end(), package.begin(), package.end());
  }
  return out;
}

// -------------------------------------------------------------------------- package scanner

SerialPackageScanner::SerialPackageScanner(std::size_t max_words) : max_words_(max_words) {}

void SerialPackageScanner::reset() {
  state_ = State::hunting;
  words_.clear();
  pending_word_ = 0;
  pending_digits_ = 0;
}

std::vector<SerialPackageScanner::Event> SerialPackageScanner::feed(ByteView chunk) {
  std::vector<Event> events;
  for (const auto byte : chunk) consume(byte, events);
  return events;
}

void SerialPackageScanner::fail(DecodeError detail, std::vector<Event>& events) {
  const std::uint16_t service_word = words_.size() > 3 ? words_[3] : std::uint16_t{0};
  events.emplace_back(Error{detail, service_word});
  reset();
}

void SerialPackageScanner::consume(std::uint8_t byte, std::vector<Event>& events) {
  switch (state_) {
    case State::hunting:
      if (byte == kSerialStx) {
        reset();
        state_ = State::body;
      } else {
        ++skipped_bytes_;
      }
      return;
    case State::body: {
      if (byte == kSerialStx) {  // a new telegram cuts the current one short
        fail(DecodeError::truncated, events);
        state_ = State::body;
        return;
      }
      if (byte == kSerialEtx) {
        finish(events);
        return;
      }
      const auto digit = hex_value(byte);
      if (!digit) {
        fail(DecodeError::bad_hex, events);
        return;
      }
      pending_word_ = static_cast<std::uint16_t>((pending_word_ << 4) | *digit);
      if (++pending_digits_ < kHexDigitsPerWord) return;
      if (words_.size() == max_words_) {
        fail(DecodeError::too_large, events);
        return;
      }
      words_.push_back(pending_word_);
      pending_word_ = 0;
      pending_digits_ = 0;
      return;
    }
  }
}

void SerialPackageScanner::finish(std::vector<Event>& events) {
  if (pending_digits_ != 0) {  // not whole WORDs
    fail(DecodeError::bad_hex, events);
    return;
  }
  if (words_.size() < 2) {  // not even an address and a CRC
    fail(DecodeError::truncated, events);
    return;
  }
  std::uint16_t crc = kCrcInitial;
  for (std::size_t i = 0; i + 1 < words_.size(); ++i) {
    crc = PackageWriter::crc_step(crc, static_cast<std::uint8_t>(words_[i] >> 8));
    crc = PackageWriter::crc_step(crc, static_cast<std::uint8_t>(words_[i] & 0xFF));
  }
  if (crc != words_.back()) {
    fail(DecodeError::bad_crc, events);
    return;
  }
  words_.pop_back();
  events.emplace_back(Package{std::move(words_)});
  reset();
}

// -------------------------------------------------------------------------- host -> LD decoder

namespace {
// address, length, package id, payload WORDs, CRC
std::size_t request_max_words(std::size_t max_payload) { return 4 + words_for(max_payload); }
// A reply package: address + at most 126 length-counted WORDs + CRC.
constexpr std::size_t kReplyPackageMaxWords = 2 + kMaxPackageLengthWord;
}  // namespace

SerialDeframer::SerialDeframer(std::size_t max_payload) : scanner_(request_max_words(max_payload)) {}

void SerialDeframer::reset() { scanner_.reset(); }

std::vector<DeframerEvent> SerialDeframer::feed(ByteView chunk) {
  std::vector<DeframerEvent> events;
  for (const auto& event : scanner_.feed(chunk)) {
    events.push_back(interpret(event));
    if (std::holds_alternative<FramingError>(events.back())) ++dropped_frames_;
  }
  return events;
}

DeframerEvent SerialDeframer::interpret(const SerialPackageScanner::Event& event) {
  if (const auto* error = std::get_if<SerialPackageScanner::Error>(&event)) {
    return FramingError{error->detail, error->service_word};
  }
  const auto& words = std::get<SerialPackageScanner::Package>(event).words;
  if (words.size() < 3) return FramingError{DecodeError::truncated, 0};
  const std::uint16_t service_word = words.size() > 3 ? words[3] : std::uint16_t{0};
  if (words[1] != words.size() - 1) return FramingError{DecodeError::bad_length, service_word};
  if (words[2] != kHostPackageId) return FramingError{DecodeError::unexpected_frame, service_word};
  return Telegram{words_to_bytes(words, 3)};
}

// -------------------------------------------------------------------------- LD -> host decoder

SerialReplyReassembler::SerialReplyReassembler(std::size_t max_payload)
    : max_payload_(max_payload), scanner_(kReplyPackageMaxWords) {}

void SerialReplyReassembler::reset() {
  scanner_.reset();
  payload_.clear();
  remaining_packages_ = 0;
}

std::vector<DeframerEvent> SerialReplyReassembler::feed(ByteView chunk) {
  std::vector<DeframerEvent> events;
  for (const auto& event : scanner_.feed(chunk)) interpret(event, events);
  return events;
}

void SerialReplyReassembler::drop(FramingError error, std::vector<DeframerEvent>& events) {
  ++dropped_frames_;
  events.emplace_back(error);
  payload_.clear();
  remaining_packages_ = 0;
}

void SerialReplyReassembler::interpret(const SerialPackageScanner::Event& event,
                                       std::vector<DeframerEvent>& events) {
  if (const auto* error = std::get_if<SerialPackageScanner::Error>(&event)) {
    drop(FramingError{error->detail, 0}, events);
    return;
  }
  const auto& words = std::get<SerialPackageScanner::Package>(event).words;
  if (words.size() < 3) {
    drop(FramingError{DecodeError::truncated, 0}, events);
    return;
  }
  if (words[1] != words.size() - 1) {
    drop(FramingError{DecodeError::bad_length, 0}, events);
    return;
  }
  const bool first_package = words[2] == kReplyFirstPackageWord2;
  if (remaining_packages_ == 0 && first_package) {
    start_reply(words, events);
  } else if (remaining_packages_ == 0) {
    drop(FramingError{DecodeError::unexpected_frame, 0}, events);
  } else if (first_package) {
    drop(FramingError{DecodeError::bad_sequence, 0}, events);  // the partial reply is lost
    start_reply(words, events);
  } else {
    continue_reply(words, events);
  }
}

void SerialReplyReassembler::start_reply(const std::vector<std::uint16_t>& words,
                                         std::vector<DeframerEvent>& events) {
  if (words.size() < 4) {
    drop(FramingError{DecodeError::bad_length, 0}, events);
    return;
  }
  const std::uint16_t package_count = words[3];
  if (package_count == 0) {
    drop(FramingError{DecodeError::bad_sequence, 0}, events);
    return;
  }
  if (package_count > max_reply_packages(max_payload_)) {
    drop(FramingError{DecodeError::too_large, 0}, events);
    return;
  }
  payload_ = words_to_bytes(words, 4);
  remaining_packages_ = static_cast<std::uint16_t>(package_count - 1);
  if (remaining_packages_ == 0) {
    events.emplace_back(Telegram{std::move(payload_)});
    payload_.clear();
  }
}

void SerialReplyReassembler::continue_reply(const std::vector<std::uint16_t>& words,
                                            std::vector<DeframerEvent>& events) {
  if (words[2] != remaining_packages_) {
    drop(FramingError{DecodeError::bad_sequence, 0}, events);
    return;
  }
  if (payload_.size() + 2 * (words.size() - 3) > max_payload_ + 1) {  // +1: odd-length padding
    drop(FramingError{DecodeError::too_large, 0}, events);
    return;
  }
  for (std::size_t i = 3; i < words.size(); ++i) append_word_be(payload_, words[i]);
  if (--remaining_packages_ == 0) {
    events.emplace_back(Telegram{std::move(payload_)});
    payload_.clear();
  }
}

}  // namespace ldoem::protocol
