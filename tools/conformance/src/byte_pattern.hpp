// What a reply must look like, byte by byte, and the hex diff a FAIL line shows.
//
// A BytePattern is a payload with "don't care" holes: --target device leaves every byte open
// that spec 7.2's "asserted positions" column does not name, and both targets leave open the
// fields nobody can predict (distances, time stamps, identification texts).
// The diff renders expected and received payloads as two hex lines with `..` for a hole and a
// caret line under every byte that differs or is missing:
//   expected: 81 02 00 00 00 01
//   received: 81 02 00 00 00 03
//                            ^^
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/protocol/bytes.hpp"

namespace ldoem::conformance {

using protocol::ByteView;
using protocol::Bytes;

enum class LengthRule : std::uint8_t {
  exact,     // the reply has exactly the pattern's length
  at_least,  // a real device may append fields nobody published (spec 7.2)
};

struct BytePattern {
  std::vector<std::optional<std::uint8_t>> bytes;  // nullopt = any value
  LengthRule length_rule = LengthRule::exact;

  static BytePattern exactly(ByteView payload);
  // Keeps only the listed positions; the others become holes. Positions past the payload are ignored.
  BytePattern keep_only(const std::vector<std::size_t>& positions) const;
  BytePattern with_hole(std::size_t position, std::size_t count = 1) const;
  BytePattern with_length_rule(LengthRule rule) const;
};

struct PatternMismatch {
  std::vector<std::size_t> differing_positions;  // includes missing and surplus bytes
  bool length_differs = false;
};

// nullopt when `received` matches.
std::optional<PatternMismatch> compare(const BytePattern& expected, ByteView received);

// "81 02 00 .. 00 01" (holes as ..).
std::string format_pattern(const BytePattern& pattern);
std::string format_hex(ByteView bytes);

// The three lines (expected, received, carets), each prefixed with `indent`, newline-terminated.
// Long payloads show only 16-byte rows that hold a difference (with their offset), so a profile
// diff stays readable.
std::string render_diff(const BytePattern& expected, ByteView received, const PatternMismatch& mismatch,
                        const std::string& indent = "    ");

// Parses "02 55 53 50 ..." (spaces optional, either case); nullopt on a bad digit or odd count.
std::optional<Bytes> parse_hex(std::string_view text);

}  // namespace ldoem::conformance
