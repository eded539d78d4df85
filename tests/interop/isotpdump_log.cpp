#include "isotpdump_log.hpp"

#include <charconv>
#include <map>
#include <regex>
#include <sstream>

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
  T value{};
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value, base);
  if (error != std::errc() || end != digits.data() + digits.size()) return std::nullopt;
  return value;
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

bool fill_fields(IsoTpFrameType type, const std::string& rest, DumpedFrame& frame) {
  std::smatch match;
  switch (type) {
    case IsoTpFrameType::single_frame:
    case IsoTpFrameType::first_frame: {
      static const std::regex length(R"(^ln: (\d+)\s)");
      if (!std::regex_search(rest, match, length)) return false;
      frame.announced_length = number<std::uint64_t>(match[1], 10);
      frame.data = data_bytes(rest);
      return frame.announced_length.has_value();
    }
    case IsoTpFrameType::consecutive_frame: {
      static const std::regex sequence(R"(^sn: ([0-9A-Fa-f])\s)");
      if (!std::regex_search(rest, match, sequence)) return false;
      frame.sequence = number<std::uint8_t>(match[1], 16);
      frame.data = data_bytes(rest);
      return true;
    }
    case IsoTpFrameType::flow_control: {
      static const std::regex fields(R"(^FC: (\d+) = \S+ # BS: (\d+).*# STmin: 0x([0-9A-Fa-f]{2}))");
      if (!std::regex_search(rest, match, fields)) return false;
      frame.flow_status = number<std::uint8_t>(match[1], 10);
      frame.block_size = number<std::uint8_t>(match[2], 10);
      frame.st_min_byte = number<std::uint8_t>(match[3], 16);
      return frame.flow_status && frame.block_size && frame.st_min_byte;
    }
  }
  return false;
}

std::optional<IsoTpFrameType> type_of(const std::string& name) {
  if (name == "SF") return IsoTpFrameType::single_frame;
  if (name == "FF") return IsoTpFrameType::first_frame;
  if (name == "CF") return IsoTpFrameType::consecutive_frame;
  if (name == "FC") return IsoTpFrameType::flow_control;
  return std::nullopt;
}

std::optional<DumpedFrame> parse_line(const std::string& line) {
  static const std::regex head(R"(^\s*\S+\s+([0-9A-Fa-f]{3,8})\s+\[(\d)\]\s+\[(SF|FF|CF|FC)\]\s+(.*)$)");
  std::smatch match;
  if (!std::regex_match(line, match, head)) return std::nullopt;
  DumpedFrame frame;
  const auto id = number<std::uint32_t>(match[1], 16);
  const auto dlc = number<std::uint8_t>(match[2], 10);
  const auto type = type_of(match[3]);
  if (!id || !dlc || !type) return std::nullopt;
  frame.id = *id;
  frame.dlc = *dlc;
  frame.type = *type;
  if (!fill_fields(*type, match[4].str() + " ", frame)) return std::nullopt;
  return frame;
}

}  // namespace

protocol::Expected<std::vector<DumpedFrame>, DumpError> parse_isotpdump(std::string_view text) {
  std::vector<DumpedFrame> frames;
  std::istringstream lines{std::string(text)};
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const std::string plain = strip_colour(line);
    if (plain.find_first_not_of(" \t\r") == std::string::npos) continue;
    auto frame = parse_line(plain);
    if (!frame) {
      return protocol::Unexpected<DumpError>("line " + std::to_string(number) +
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
