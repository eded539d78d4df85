// Number and hex text helpers shared by the hub's request parser and its typed reply fields.
#pragma once

#include <charconv>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/base/numbers.hpp"
#include "ldoem/protocol/bytes.hpp"

namespace ldoem::hub::text {

using base::parse_double;
using base::parse_integer;

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
