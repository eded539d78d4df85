// Pieces shared by the PLY and PCD codecs (internal): little-endian bytes, number text, header
// lines and whitespace tokens, each reading strictly inside the given bytes.
#pragma once

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/base/numbers.hpp"

namespace ldoem::cloud::detail {

// Both formats store binary numbers little-endian whatever the host is, so bytes are
// assembled one at a time rather than copied.
template <class Unsigned>
void append_uint_le(std::string& out, Unsigned value) {
  for (std::size_t byte = 0; byte < sizeof(Unsigned); ++byte) {
    out.push_back(static_cast<char>((value >> (8 * byte)) & 0xFFU));
  }
}

inline void append_float_le(std::string& out, float value) {
  append_uint_le(out, std::bit_cast<std::uint32_t>(value));
}

template <class Unsigned>
Unsigned read_uint_le(std::string_view bytes, std::size_t offset) {
  Unsigned value = 0;
  for (std::size_t byte = 0; byte < sizeof(Unsigned); ++byte) {
    value |= static_cast<Unsigned>(static_cast<Unsigned>(static_cast<unsigned char>(bytes[offset + byte]))
                                   << (8 * byte));
  }
  return value;
}

// Shortest text that reads back to the same float ("nan", "inf", "-inf" for the rest).
inline void append_float_text(std::string& out, float value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

inline void append_uint_text(std::string& out, std::uint64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

// Whole token must be a number. "nan" and "inf" are accepted: files store NaN for no echo. A
// leading '+' is accepted too, as other writers put it there and from_chars does not take it.
inline std::optional<double> parse_double(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  return base::parse_double(token, base::NonFinite::accept);
}

inline std::optional<std::uint64_t> parse_unsigned(std::string_view token) {
  return base::parse_integer<std::uint64_t>(token);
}

// Scalar types both formats can describe.
enum class ScalarType : std::uint8_t { i8, u8, i16, u16, i32, u32, i64, u64, f32, f64 };

constexpr std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::i8:
    case ScalarType::u8: return 1;
    case ScalarType::i16:
    case ScalarType::u16: return 2;
    case ScalarType::i32:
    case ScalarType::u32:
    case ScalarType::f32: return 4;
    case ScalarType::i64:
    case ScalarType::u64:
    case ScalarType::f64: return 8;
  }
  return 0;
}

// Precondition: offset + scalar_size(type) <= bytes.size() (callers check whole records).
inline double read_scalar_le(std::string_view bytes, std::size_t offset, ScalarType type) {
  switch (type) {
    case ScalarType::i8: return static_cast<std::int8_t>(read_uint_le<std::uint8_t>(bytes, offset));
    case ScalarType::u8: return read_uint_le<std::uint8_t>(bytes, offset);
    case ScalarType::i16: return static_cast<std::int16_t>(read_uint_le<std::uint16_t>(bytes, offset));
    case ScalarType::u16: return read_uint_le<std::uint16_t>(bytes, offset);
    case ScalarType::i32: return static_cast<std::int32_t>(read_uint_le<std::uint32_t>(bytes, offset));
    case ScalarType::u32: return read_uint_le<std::uint32_t>(bytes, offset);
    case ScalarType::i64:
      return static_cast<double>(static_cast<std::int64_t>(read_uint_le<std::uint64_t>(bytes, offset)));
    case ScalarType::u64: return static_cast<double>(read_uint_le<std::uint64_t>(bytes, offset));
    case ScalarType::f32: return std::bit_cast<float>(read_uint_le<std::uint32_t>(bytes, offset));
    case ScalarType::f64: return std::bit_cast<double>(read_uint_le<std::uint64_t>(bytes, offset));
  }
  return 0.0;
}

// A ring value read from a file of any numeric type, saturated into uint16.
inline std::uint16_t to_ring(double value) {
  if (!(value > 0.0)) return 0;
  if (value >= 65535.0) return 65535;
  return static_cast<std::uint16_t>(value);
}

// Walks text one line at a time ('\n', with an optional '\r' before it) without leaving it.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  // The next line without its terminator, or nothing when no complete line is left.
  std::optional<std::string_view> next_line() {
    const std::size_t end = text_.find('\n', offset_);
    if (end == std::string_view::npos) return std::nullopt;
    std::string_view line = text_.substr(offset_, end - offset_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    offset_ = end + 1;
    return line;
  }
  std::size_t offset() const { return offset_; }

 private:
  std::string_view text_;
  std::size_t offset_ = 0;
};

// Whitespace-separated tokens of a text (ASCII bodies and header lines).
class TokenCursor {
 public:
  explicit TokenCursor(std::string_view text) : text_(text) {}
  std::optional<std::string_view> next() {
    while (offset_ < text_.size() && is_space(text_[offset_])) ++offset_;
    if (offset_ >= text_.size()) return std::nullopt;
    const std::size_t begin = offset_;
    while (offset_ < text_.size() && !is_space(text_[offset_])) ++offset_;
    return text_.substr(begin, offset_ - begin);
  }
  // True when the last token ran up to the end of the text (no separator after it).
  bool at_end() const { return offset_ >= text_.size(); }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
  std::string_view text_;
  std::size_t offset_ = 0;
};

// Index of the field named `name` among `names`, or nothing.
template <class Range>
std::optional<std::size_t> find_name(const Range& names, std::string_view name) {
  std::size_t index = 0;
  for (const auto& candidate : names) {
    if (candidate == name) return index;
    ++index;
  }
  return std::nullopt;
}

}  // namespace ldoem::cloud::detail
