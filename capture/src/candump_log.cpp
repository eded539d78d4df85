#include "ldoem/capture/candump_log.hpp"

#include <array>
#include <cstdio>

namespace ldoem::capture {
namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view trim(std::string_view text) {
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

// "(seconds.fraction)" -> nanoseconds. At most 10 integer digits (year 2286) keeps nanoseconds within 64 bits.
bool parse_time(std::string_view text, std::uint64_t& time_ns) {
  if (text.size() < 3 || text.front() != '(' || text.back() != ')') return false;
  text = text.substr(1, text.size() - 2);
  const std::size_t dot = text.find('.');
  const std::string_view seconds = text.substr(0, dot);
  const std::string_view fraction = dot == std::string_view::npos ? std::string_view{} : text.substr(dot + 1);
  if (seconds.empty() || seconds.size() > 10 || (dot != std::string_view::npos && fraction.empty())) return false;
  std::uint64_t whole = 0;
  for (char c : seconds) {
    if (c < '0' || c > '9') return false;
    whole = whole * 10 + static_cast<std::uint64_t>(c - '0');
  }
  std::uint64_t nanos = 0;
  std::size_t digits = 0;
  for (char c : fraction) {
    if (c < '0' || c > '9') return false;
    if (digits < 9) {
      nanos = nanos * 10 + static_cast<std::uint64_t>(c - '0');
      ++digits;
    }
  }
  for (; digits < 9; ++digits) nanos *= 10;
  time_ns = whole * 1'000'000'000ull + nanos;
  return true;
}

}  // namespace

std::string_view describe(CandumpError error) {
  switch (error) {
    case CandumpError::bad_timestamp: return "no (seconds.fraction) timestamp at the start of the line";
    case CandumpError::missing_field: return "line lacks the interface or the frame";
    case CandumpError::bad_identifier: return "CAN identifier is not 3 or 8 hex digits";
    case CandumpError::bad_data: return "frame data is not up to 8 bytes as hex pairs";
    case CandumpError::unsupported: return "CAN FD or XL frame: ldoem's CAN transport (D1) is classic CAN";
  }
  return "unknown candump error";
}

base::Expected<CandumpEntry, CandumpError> parse_candump_line(std::string_view line) {
  line = trim(line);
  const std::size_t first_space = line.find_first_of(" \t");
  if (first_space == std::string_view::npos) {
    return base::Unexpected(line.starts_with('(') ? CandumpError::missing_field : CandumpError::bad_timestamp);
  }
  CandumpEntry entry;
  if (!parse_time(line.substr(0, first_space), entry.time_ns)) return base::Unexpected(CandumpError::bad_timestamp);
  std::string_view rest = trim(line.substr(first_space));
  const std::size_t second_space = rest.find_first_of(" \t");
  if (second_space == std::string_view::npos) return base::Unexpected(CandumpError::missing_field);
  entry.interface = std::string(rest.substr(0, second_space));
  rest = trim(rest.substr(second_space));
  // Newer can-utils may append a direction flag (" R" / " T"): not part of the frame.
  if (const std::size_t space = rest.find_first_of(" \t"); space != std::string_view::npos) {
    const std::string_view flag = trim(rest.substr(space));
    if (flag != "R" && flag != "T") return base::Unexpected(CandumpError::bad_data);
    rest = rest.substr(0, space);
  }
  const std::size_t hash = rest.find('#');
  if (hash == std::string_view::npos) return base::Unexpected(CandumpError::missing_field);
  const std::string_view id_text = rest.substr(0, hash);
  std::string_view data_text = rest.substr(hash + 1);
  if (id_text.size() != 3 && id_text.size() != 8) return base::Unexpected(CandumpError::bad_identifier);
  std::uint32_t id = 0;
  for (char c : id_text) {
    const int value = hex_value(c);
    if (value < 0) return base::Unexpected(CandumpError::bad_identifier);
    id = (id << 4) | static_cast<std::uint32_t>(value);
  }
  if (id_text.size() == 3 && id > protocol::kCanStandardIdMask) return base::Unexpected(CandumpError::bad_identifier);
  if (id_text.size() == 8 && id > 0x1FFFFFFF) return base::Unexpected(CandumpError::bad_identifier);
  entry.extended_id = id_text.size() == 8;
  if (data_text.starts_with('#')) return base::Unexpected(CandumpError::unsupported);
  if (data_text.starts_with('R') || data_text.starts_with('r')) {
    entry.remote = true;
    data_text.remove_prefix(1);
    if (data_text.size() > 1 || (data_text.size() == 1 && (data_text[0] < '0' || data_text[0] > '8'))) {
      return base::Unexpected(CandumpError::bad_data);
    }
    entry.frame.id = id;
    entry.frame.length = data_text.empty() ? 0 : static_cast<std::uint8_t>(data_text[0] - '0');
    return entry;
  }
  if (data_text.size() % 2 != 0 || data_text.size() > 2 * protocol::kCanMaxDataBytes) return base::Unexpected(CandumpError::bad_data);
  entry.frame.id = id;
  entry.frame.length = static_cast<std::uint8_t>(data_text.size() / 2);
  for (std::size_t i = 0; i < entry.frame.length; ++i) {
    const int high = hex_value(data_text[2 * i]);
    const int low = hex_value(data_text[2 * i + 1]);
    if (high < 0 || low < 0) return base::Unexpected(CandumpError::bad_data);
    entry.frame.data[i] = static_cast<std::uint8_t>((high << 4) | low);
  }
  return entry;
}

base::Expected<std::vector<CandumpEntry>, CandumpFailure> parse_candump_log(std::string_view text) {
  std::vector<CandumpEntry> entries;
  std::size_t line_number = 0;
  while (!text.empty()) {
    ++line_number;
    const std::size_t newline = text.find('\n');
    const std::string_view line = trim(text.substr(0, newline));
    text = newline == std::string_view::npos ? std::string_view{} : text.substr(newline + 1);
    if (line.empty() || line.starts_with('#')) continue;
    auto entry = parse_candump_line(line);
    if (!entry) return base::Unexpected(CandumpFailure{entry.error(), line_number});
    entries.push_back(std::move(*entry));
  }
  return entries;
}

std::string format_candump_line(std::uint64_t time_ns, std::string_view interface, const protocol::CanFrame& frame) {
  std::array<char, 40> head{};
  std::snprintf(head.data(), head.size(), "(%llu.%06llu) ",
                static_cast<unsigned long long>(time_ns / 1'000'000'000ull),
                static_cast<unsigned long long>((time_ns % 1'000'000'000ull) / 1000));
  std::string line = head.data();
  line += interface;
  std::array<char, 8> id{};
  std::snprintf(id.data(), id.size(), " %03X#", static_cast<unsigned>(frame.id & protocol::kCanStandardIdMask));
  line += id.data();
  static constexpr char kDigits[] = "0123456789ABCDEF";
  for (std::uint8_t byte : frame.payload()) {
    line += kDigits[byte >> 4];
    line += kDigits[byte & 0xF];
  }
  return line;
}

bool looks_like_candump_log(std::string_view text) {
  text = trim(text);
  return text.size() >= 2 && text[0] == '(' && text[1] >= '0' && text[1] <= '9';
}

}  // namespace ldoem::capture
