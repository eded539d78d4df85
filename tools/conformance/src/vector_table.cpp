#include "vector_table.hpp"

#include <algorithm>
#include <cctype>
#include <yaml-cpp/yaml.h>

#include "ldoem/protocol/tcp_framing.hpp"

namespace ldoem::conformance {
namespace {

using base::Expected;
using base::Unexpected;

Unexpected<std::string> error(std::string text) { return Unexpected<std::string>(std::move(text)); }

std::string trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  return std::string(text);
}

std::vector<std::string> split_commas(std::string_view text) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? text.size() : comma;
    parts.push_back(trim(text.substr(start, end - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return parts;
}

std::optional<std::size_t> parse_index(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::size_t value = 0;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
    value = value * 10 + static_cast<std::size_t>(c - '0');
  }
  return value;
}

// "payload[0..1]", "[3]", "payload[5]" -> the offsets.
std::optional<std::vector<std::size_t>> parse_range(std::string_view item) {
  if (item.starts_with("payload")) item.remove_prefix(7);
  if (item.size() < 3 || item.front() != '[' || item.back() != ']') return std::nullopt;
  item = item.substr(1, item.size() - 2);
  const std::size_t dots = item.find("..");
  const auto first = parse_index(item.substr(0, dots));
  const auto last = dots == std::string_view::npos ? first : parse_index(item.substr(dots + 2));
  if (!first || !last || *last < *first) return std::nullopt;
  std::vector<std::size_t> positions;
  for (std::size_t i = *first; i <= *last; ++i) positions.push_back(i);
  return positions;
}

// One TCP frame of the table -> its payload, checking the frame as spec 4.1 defines it.
Expected<Bytes, std::string> frame_payload(const std::string& where, const std::string& hex) {
  const auto frame = parse_hex(hex);
  if (!frame) return error(where + ": not a hex byte string");
  protocol::TcpDeframer deframer;
  const auto events = deframer.feed(*frame);
  if (events.size() != 1 || !std::holds_alternative<protocol::Telegram>(events.front())) {
    return error(where + ": not exactly one valid TCP frame (spec 4.1)");
  }
  return std::get<protocol::Telegram>(events.front()).payload;
}

}  // namespace

BytePattern ReplyVector::emulator_pattern() const { return BytePattern::exactly(payload); }

BytePattern ReplyVector::device_pattern() const {
  BytePattern pattern = BytePattern::exactly(payload);
  if (asserted.all) return pattern.with_hole(payload.size() - 1 - asserted.senstat_hole_bytes, asserted.senstat_hole_bytes);
  return pattern.keep_only(asserted.positions).with_length_rule(LengthRule::at_least);
}

Bytes SerialVector::telegram() const {
  Bytes bytes(ascii.size() + 2, 0x02);  // STX ... ETX (spec 4.2)
  std::copy(ascii.begin(), ascii.end(), bytes.begin() + 1);
  bytes.back() = 0x03;
  return bytes;
}

const RequestVector* VectorTable::request(std::string_view name) const {
  auto found = std::find_if(tcp_requests.begin(), tcp_requests.end(), [&](const auto& v) { return v.name == name; });
  return found == tcp_requests.end() ? nullptr : &*found;
}

const ReplyVector* VectorTable::reply(std::string_view name) const {
  auto found = std::find_if(tcp_replies.begin(), tcp_replies.end(), [&](const auto& v) { return v.name == name; });
  return found == tcp_replies.end() ? nullptr : &*found;
}

const SerialVector* VectorTable::serial(std::string_view name) const {
  auto found =
      std::find_if(serial_requests.begin(), serial_requests.end(), [&](const auto& v) { return v.name == name; });
  return found == serial_requests.end() ? nullptr : &*found;
}

Expected<AssertedPositions, std::string> parse_asserted(std::string_view text, const AssertedPositions& previous) {
  const std::string column = trim(text);
  if (column == "idem") return previous;
  if (column == "all") return AssertedPositions{true, {}, 0};
  // The GET_IDENTIFICATION text is illustrative: only the code is the device's.
  if (column == "structure only") return AssertedPositions{false, {0, 1}, 0};
  if (column.starts_with("all except SENSTAT bytes 0")) return AssertedPositions{true, {}, 3};
  AssertedPositions asserted;
  std::string_view rest = column;
  if (rest.starts_with("+")) {
    asserted = previous;
    rest.remove_prefix(1);
  }
  for (const std::string& item : split_commas(rest)) {
    const auto positions = parse_range(item);
    if (!positions) return error("cannot read asserted positions `" + column + "`");
    asserted.positions.insert(asserted.positions.end(), positions->begin(), positions->end());
  }
  return asserted;
}

Expected<VectorTable, std::string> load_vector_table(std::string_view yaml_text) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    return error(std::string("vectors: ") + e.what());
  }
  VectorTable table;
  std::size_t row = 0;
  for (const auto& node : root["tcp_requests"]) {
    const std::string where = "tcp_requests[" + std::to_string(row++) + "]";
    auto payload = frame_payload(where, node["frame"].as<std::string>(""));
    if (!payload) return error(payload.error());
    table.tcp_requests.push_back({node["name"].as<std::string>(""), std::move(*payload)});
  }
  row = 0;
  AssertedPositions previous;
  for (const auto& node : root["tcp_replies"]) {
    const std::string where = "tcp_replies[" + std::to_string(row++) + "]";
    auto payload = frame_payload(where, node["frame"].as<std::string>(""));
    if (!payload) return error(payload.error());
    auto asserted = parse_asserted(node["asserted"].as<std::string>("all"), previous);
    if (!asserted) return error(where + ".asserted: " + asserted.error());
    previous = *asserted;
    table.tcp_replies.push_back({node["name"].as<std::string>(""), std::move(*payload), *asserted});
  }
  for (const auto& node : root["serial_requests"]) {
    table.serial_requests.push_back({node["name"].as<std::string>(""), node["ascii"].as<std::string>("")});
  }
  if (table.tcp_requests.empty() || table.tcp_replies.empty()) return error("vectors: no tcp_requests/tcp_replies");
  return table;
}

}  // namespace ldoem::conformance
