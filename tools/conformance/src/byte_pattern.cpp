#include "byte_pattern.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <set>

namespace ldoem::conformance {
namespace {

constexpr std::size_t kBytesPerRow = 16;
// Below this size the whole payload is shown on one row.
constexpr std::size_t kSingleRowLimit = 24;

std::string hex_byte(std::uint8_t byte) {
  char text[3];
  std::snprintf(text, sizeof text, "%02x", byte);
  return text;
}

std::string cell(const std::optional<std::uint8_t>& byte) { return byte ? hex_byte(*byte) : ".."; }

std::string row_text(const std::vector<std::string>& cells, std::size_t first, std::size_t count) {
  std::string text;
  for (std::size_t i = first; i < first + count; ++i) {
    if (i > first) text += ' ';
    text += i < cells.size() ? cells[i] : "  ";
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

std::string caret_text(const std::set<std::size_t>& marks, std::size_t first, std::size_t count) {
  std::string text;
  for (std::size_t i = first; i < first + count; ++i) {
    if (i > first) text += ' ';
    text += marks.count(i) ? "^^" : "  ";
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

BytePattern BytePattern::exactly(ByteView payload) {
  BytePattern pattern;
  pattern.bytes.assign(payload.begin(), payload.end());
  return pattern;
}

BytePattern BytePattern::keep_only(const std::vector<std::size_t>& positions) const {
  BytePattern kept = *this;
  std::fill(kept.bytes.begin(), kept.bytes.end(), std::nullopt);
  for (std::size_t position : positions) {
    if (position < bytes.size()) kept.bytes[position] = bytes[position];
  }
  return kept;
}

BytePattern BytePattern::with_hole(std::size_t position, std::size_t count) const {
  BytePattern holed = *this;
  for (std::size_t i = position; i < position + count && i < holed.bytes.size(); ++i) holed.bytes[i] = std::nullopt;
  return holed;
}

BytePattern BytePattern::with_length_rule(LengthRule rule) const {
  BytePattern changed = *this;
  changed.length_rule = rule;
  return changed;
}

std::optional<PatternMismatch> compare(const BytePattern& expected, ByteView received) {
  PatternMismatch mismatch;
  const std::size_t common = std::min(expected.bytes.size(), received.size());
  for (std::size_t i = 0; i < common; ++i) {
    if (expected.bytes[i] && *expected.bytes[i] != received[i]) mismatch.differing_positions.push_back(i);
  }
  for (std::size_t i = common; i < expected.bytes.size(); ++i) mismatch.differing_positions.push_back(i);
  if (expected.length_rule == LengthRule::exact) {
    for (std::size_t i = common; i < received.size(); ++i) mismatch.differing_positions.push_back(i);
  }
  mismatch.length_differs = received.size() < expected.bytes.size() ||
                            (expected.length_rule == LengthRule::exact && received.size() != expected.bytes.size());
  if (mismatch.differing_positions.empty() && !mismatch.length_differs) return std::nullopt;
  return mismatch;
}

std::string format_pattern(const BytePattern& pattern) {
  std::vector<std::string> cells;
  for (const auto& byte : pattern.bytes) cells.push_back(cell(byte));
  return row_text(cells, 0, cells.size());
}

std::string format_hex(ByteView bytes) {
  std::string text;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i > 0) text += ' ';
    text += hex_byte(bytes[i]);
  }
  return text;
}

std::string render_diff(const BytePattern& expected, ByteView received, const PatternMismatch& mismatch,
                        const std::string& indent) {
  std::vector<std::string> expected_cells;
  for (const auto& byte : expected.bytes) expected_cells.push_back(cell(byte));
  if (expected.length_rule == LengthRule::at_least) expected_cells.push_back("+");
  std::vector<std::string> received_cells;
  for (std::uint8_t byte : received) received_cells.push_back(hex_byte(byte));
  const std::set<std::size_t> marks(mismatch.differing_positions.begin(), mismatch.differing_positions.end());
  const std::size_t total = std::max(expected.bytes.size(), received.size());

  std::string text;
  auto add_row = [&](std::size_t first, std::size_t count, const std::string& label_suffix) {
    text += indent + "expected" + label_suffix + ": " + row_text(expected_cells, first, count) + "\n";
    text += indent + "received" + label_suffix + ": " + row_text(received_cells, first, count) + "\n";
    text += indent + std::string(10 + label_suffix.size(), ' ') + caret_text(marks, first, count) + "\n";
  };
  if (total <= kSingleRowLimit) {
    add_row(0, total + 1, "");
    return text;
  }
  text += indent + "(" + std::to_string(received.size()) + " bytes received, " +
          std::to_string(expected.bytes.size()) + " expected; rows with differences)\n";
  std::size_t rows_shown = 0;
  for (std::size_t first = 0; first < total && rows_shown < 6; first += kBytesPerRow) {
    const bool row_differs =
        std::any_of(marks.begin(), marks.end(), [&](std::size_t m) { return m >= first && m < first + kBytesPerRow; });
    if (!row_differs) continue;
    char label[32];
    std::snprintf(label, sizeof label, "@%04zx", first);
    add_row(first, kBytesPerRow, label);
    ++rows_shown;
  }
  return text;
}

std::optional<Bytes> parse_hex(std::string_view text) {
  Bytes bytes;
  int pending = -1;
  for (char c : text) {
    if (c == ' ') continue;
    if (!std::isxdigit(static_cast<unsigned char>(c))) return std::nullopt;
    const int nibble = std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : std::tolower(c) - 'a' + 10;
    if (pending < 0) {
      pending = nibble;
    } else {
      bytes.push_back(static_cast<std::uint8_t>((pending << 4) | nibble));
      pending = -1;
    }
  }
  if (pending >= 0) return std::nullopt;
  return bytes;
}

}  // namespace ldoem::conformance
