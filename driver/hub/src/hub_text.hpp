// Number and hex text helpers shared by the hub's request parser and its typed reply fields.
#pragma once

#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::hub::text {

template <class Integer>
inline std::optional<Integer> parse_integer(std::string_view text, int base = 10) {
  Integer value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) {
    return std::nullopt;
  }
  return value;
}

inline std::optional<double> parse_double(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

inline std::string format_double(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

inline char hex_digit(unsigned value) { return "0123456789ABCDEF"[value & 0xF]; }

// Upper-case hex, two digits per byte.
std::string hex_of(protocol::ByteView bytes);
// nullopt for an odd length or a non-hex digit.
std::optional<protocol::Bytes> bytes_of_hex(std::string_view text);

}  // namespace ldoem::hub::text
