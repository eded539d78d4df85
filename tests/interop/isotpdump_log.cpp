#include "isotpdump_log.hpp"

#include <map>
#include <optional>
#include <string_view>
#include <sstream>

#include "ldoem/base/numbers.hpp"

namespace ldoem::interop {
namespace {

using protocol::IsoTpFrameType;

// -c wraps each line in ANSI SGR sequences (ESC [ ... m).
std::string strip_colour(std::string_view line) {
  std::string plain;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '\x1b' && i + 1 < line.size() && line[i + 1] == '[') {
      const std::size_t end = line.find('m', i);
      if (end == std::string_view::npos) break;
      i = end;
      continue;
    }
    plain.push_back(line[i]);
  }
  return plain;
}

template <class T>
std::optional<T> number(const std::string& digits, int base) {
  return ldoem::base::parse_integer<T>(digits, base);
}

// The "HH HH .." after "data:", up to the first token that is not two hex digits (the ASCII
// column of -a starts with "-").
protocol::Bytes data_bytes(const std::string& rest) {
  protocol::Bytes bytes;
  const std::size_t start = rest.find("data:");
  if (start == std::string::npos) return bytes;
  std::istringstream tokens(rest.substr(start + 5));
  std::string token;
  while (tokens >> token) {
    const auto byte = token.size() == 2 ? number<std::uint8_t>(token, 16) : std::nullopt;
    if (!byte) break;
    bytes.push_back(*byte);
  }
  return bytes;
}

// A cursor over one line. std::regex is avoided: g++ 12 warns inside it under ASan at -O1.
class Cursor {
 public:
  explicit Cursor(std::string_view text) : rest_(text) {}

  // Skips blanks; true if at least `at_least` were skipped.
  bool skip_blanks(std::size_t at_least = 0) {
    std::size_t count = 0;
    while (!rest_.empty() && (rest_.front() == ' ' || rest_.front() == '\t' || rest_.front() == '\r')) {
      rest_.remove_prefix(1);
      ++count;
    }
    return count >= at_least;
  }
  // The next run of non-blank characters (empty at the end).
  std::string_view token() {
    std::size_t length = 0;
    while (length < rest_.size() && rest_[length] != ' ' && rest_[length] != '\t' && rest_[length] != '\r') ++length;
    const std::string_view taken = rest_.substr(0, length);
    rest_.remove_prefix(length);
    return taken;
  }
  bool literal(std::string_view text) {
    if (!rest_.starts_with(text)) return false;
    rest_.remove_prefix(text.size());
    return true;
  }
  // Between min and max digits of `base` (10 or 16).
  std::optional<std::string> digits(int base, std::size_t min, std::size_t max) {
    std::size_t length = 0;
    while (length < rest_.size() && length < max && is_digit(rest_[length], base)) ++length;
    if (length < min || (length < rest_.size() && length == max && is_digit(rest_[length], base))) return std::nullopt;
    std::string taken(rest_.substr(0, length));
    rest_.remove_prefix(length);
    return taken;
  }
  // Moves past the first occurrence of `text`.
  bool past(std::string_view text) {
    const std::size_t at = rest_.find(text);
    if (at == std::string_view::npos) return false;
    rest_.remove_prefix(at + text.size());
    return true;
  }
  bool at_blank() const { return !rest_.empty() && (rest_.front() == ' ' || rest_.front() == '\t'); }
  std::string_view rest() const { return rest_; }

 private:
  static bool is_digit(char c, int base) {
    if (c >= '0' && c <= '9') return true;
    return base == 16 && ((c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'));
  }
  std::string_view rest_;
};

bool fill_fields(IsoTpFrameType type, const std::string& rest, DumpedFrame& frame) {
  Cursor cursor(rest);
  switch (type) {
    case IsoTpFrameType::single_frame:
    case IsoTpFrameType::first_frame: {
      if (!cursor.literal("ln: ")) return false;
      const auto length = cursor.digits(10, 1, 20);
      if (!length || !cursor.at_blank()) return false;
      frame.announced_length = number<std::uint64_t>(*length, 10);
      frame.data = data_bytes(rest);
      return frame.announced_length.has_value();
    }
    case IsoTpFrameType::consecutive_frame: {
      if (!cursor.literal("sn: ")) return false;
      const auto sequence = cursor.digits(16, 1, 1);
      if (!sequence || !cursor.at_blank()) return false;
      frame.sequence = number<std::uint8_t>(*sequence, 16);
      frame.data = data_bytes(rest);
      return true;
    }
    case IsoTpFrameType::flow_control: {
      // "FC: <status> = <name> # BS: <n> ... # STmin: 0x<hh>"
      if (!cursor.literal("FC: ")) return false;
      const auto status = cursor.digits(10, 1, 3);
      if (!status || !cursor.literal(" = ") || cursor.token().empty() || !cursor.literal(" # BS: ")) return false;
      const auto block_size = cursor.digits(10, 1, 3);
      if (!block_size || !cursor.past("# STmin: 0x")) return false;
      const auto st_min = cursor.digits(16, 2, 2);
      if (!st_min) return false;
      frame.flow_status = number<std::uint8_t>(*status, 10);
      frame.block_size = number<std::uint8_t>(*block_size, 10);
      frame.st_min_byte = number<std::uint8_t>(*st_min, 16);
      return frame.flow_status && frame.block_size && frame.st_min_byte;
    }
  }
  return false;
}

std::optional<IsoTpFrameType> type_of(std::string_view name) {
  if (name == "[SF]") return IsoTpFrameType::single_frame;
  if (name == "[FF]") return IsoTpFrameType::first_frame;
  if (name == "[CF]") return IsoTpFrameType::consecutive_frame;
  if (name == "[FC]") return IsoTpFrameType::flow_control;
  return std::nullopt;
}

// "<interface> <id: 3..8 hex> [<dlc digit>] [SF|FF|CF|FC] <fields>"
std::optional<DumpedFrame> parse_line(const std::string& line) {
  Cursor cursor(line);
  cursor.skip_blanks();
  if (cursor.token().empty() || !cursor.skip_blanks(1)) return std::nullopt;
  const auto id_digits = cursor.digits(16, 3, 8);
  if (!id_digits || !cursor.skip_blanks(1) || !cursor.literal("[")) return std::nullopt;
  const auto dlc_digit = cursor.digits(10, 1, 1);
  if (!dlc_digit || !cursor.literal("]") || !cursor.skip_blanks(1)) return std::nullopt;
  const auto type = type_of(cursor.token());
  if (!type || !cursor.skip_blanks(1)) return std::nullopt;
  DumpedFrame frame;
  const auto id = number<std::uint32_t>(*id_digits, 16);
  const auto dlc = number<std::uint8_t>(*dlc_digit, 10);
  if (!id || !dlc) return std::nullopt;
  frame.id = *id;
  frame.dlc = *dlc;
  frame.type = *type;
  if (!fill_fields(*type, std::string(cursor.rest()) + " ", frame)) return std::nullopt;
  return frame;
}

}  // namespace

base::Expected<std::vector<DumpedFrame>, DumpError> parse_isotpdump(std::string_view text) {
  std::vector<DumpedFrame> frames;
  std::istringstream lines{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const std::string plain = strip_colour(line);
    if (plain.find_first_not_of(" \t\r") == std::string::npos) continue;
    auto frame = parse_line(plain);
    if (!frame) {
      return base::Unexpected<DumpError>("line " + std::to_string(number) +
                                             ": not an isotpdump frame line: " + plain);
    }
    frames.push_back(std::move(*frame));
  }
  return frames;
}

namespace {

struct Running {
  DumpedMessage message;
  std::uint64_t length = 0;
  std::uint8_t next_sequence = 1;
};

std::string hex_id(std::uint32_t id) {
  std::ostringstream text;
  text << std::uppercase << std::hex << id;
  return text.str();
}

}  // namespace

Reassembly reassemble(const std::vector<DumpedFrame>& frames) {
  Reassembly result;
  std::map<std::uint32_t, Running> running;
  auto complete = [&](std::uint32_t id, Running& message) {
    message.message.payload.resize(message.length);
    result.messages.push_back(std::move(message.message));
    running.erase(id);
  };
  for (const DumpedFrame& frame : frames) {
    const std::string who = hex_id(frame.id) + ": ";
    const auto open = running.find(frame.id);
    switch (frame.type) {
      case IsoTpFrameType::single_frame:
      case IsoTpFrameType::first_frame: {
        if (open != running.end()) {
          result.problems.push_back(who + "a new SF/FF interrupts a message");
          running.erase(open);
        }
        Running& message = running[frame.id];
        message = Running{DumpedMessage{frame.id, frame.data, 1}, frame.announced_length.value_or(0), 1};
        if (message.message.payload.size() >= message.length) complete(frame.id, message);
        break;
      }
      case IsoTpFrameType::consecutive_frame: {
        if (open == running.end()) {
          result.problems.push_back(who + "CF without a first frame");
          break;
        }
        Running& message = open->second;
        if (frame.sequence != message.next_sequence) {
          result.problems.push_back(who + "CF sn " + std::to_string(frame.sequence.value_or(99)) + " where " +
                                    std::to_string(message.next_sequence) + " was due");
          running.erase(open);
          break;
        }
        message.next_sequence = static_cast<std::uint8_t>((message.next_sequence + 1) & 0x0F);
        message.message.payload.insert(message.message.payload.end(), frame.data.begin(), frame.data.end());
        ++message.message.frames;
        if (message.message.payload.size() >= message.length) complete(frame.id, message);
        break;
      }
      case IsoTpFrameType::flow_control:
        break;  // not part of a message's bytes
    }
  }
  for (const auto& [id, message] : running) result.unfinished_ids.push_back(id);
  return result;
}

}  // namespace ldoem::interop
