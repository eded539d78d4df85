#include "ldoem/control/flash_image.hpp"

#include <string>
#include <vector>

#include "ldoem/base/numbers.hpp"

namespace ldoem::control {
namespace {

using protocol::Bytes;
using protocol::ByteView;
using base::Expected;
using base::Unexpected;

void append_record(std::string& out, std::string_view name, std::initializer_list<unsigned> values) {
  out += name;
  for (const unsigned value : values) {
    out += ' ';
    out += std::to_string(value);
  }
  out += '\n';
}

// A line split into its record name and numeric fields.
struct Record {
  std::string_view name;
  std::vector<std::uint16_t> fields;
};

// Splits `text` into lines; every line, including the last, must end with '\n'.
Expected<std::vector<std::string_view>, FlashError> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    if (end == std::string_view::npos) return Unexpected(FlashError{FlashErrorKind::malformed_line, lines.size() + 1});
    lines.push_back(text.substr(0, end));
    text.remove_prefix(end + 1);
  }
  return lines;
}

Expected<Record, FlashError> parse_record(std::string_view line, std::size_t line_number) {
  const FlashError malformed{FlashErrorKind::malformed_line, line_number};
  Record record;
  std::size_t space = line.find(' ');
  record.name = line.substr(0, space);
  if (record.name.empty()) return Unexpected(malformed);
  while (space != std::string_view::npos) {
    line.remove_prefix(space + 1);
    space = line.find(' ');
    const std::string_view token = line.substr(0, space);
    const std::optional<unsigned long> value = base::parse_integer<unsigned long>(token);
    if (!value) return Unexpected(malformed);
    // serialise_flash_image writes no leading zeros, so "025" is not its image of 25 (fuzz_flash_image).
    if (token.size() > 1 && token.front() == '0') return Unexpected(malformed);
    if (*value > 0xFFFF) return Unexpected(FlashError{FlashErrorKind::value_out_of_range, line_number});
    record.fields.push_back(static_cast<std::uint16_t>(*value));
  }
  return record;
}

// Reads the records in their fixed order, one line each.
class RecordReader {
 public:
  explicit RecordReader(std::vector<std::string_view> lines) : lines_(std::move(lines)) {}

  // The fields of the next line, which must be `name` with exactly `count` fields.
  Expected<std::vector<std::uint16_t>, FlashError> next(std::string_view name, std::size_t count) {
    const std::size_t line_number = index_ + 1;
    if (index_ >= lines_.size()) return Unexpected(FlashError{FlashErrorKind::malformed_line, line_number});
    auto record = parse_record(lines_[index_++], line_number);
    if (!record) return Unexpected(record.error());
    if (record->name != name || record->fields.size() != count) {
      return Unexpected(FlashError{FlashErrorKind::malformed_line, line_number});
    }
    return std::move(record->fields);
  }
  std::size_t line_number() const { return index_; }
  bool at_end() const { return index_ == lines_.size(); }

 private:
  std::vector<std::string_view> lines_;
  std::size_t index_ = 0;
};

Expected<DeviceConfig, FlashError> parse_records(RecordReader& reader) {
  DeviceConfig config;
  auto global = reader.next("global", 3);
  if (!global) return Unexpected(global.error());
  config.global = protocol::GlobalConfig{(*global)[0], (*global)[1], (*global)[2], false};
  auto interlace = reader.next("interlace", 1);
  if (!interlace) return Unexpected(interlace.error());
  config.interlace.mode = (*interlace)[0];
  auto ethernet = reader.next("ethernet", 14);
  if (!ethernet) return Unexpected(ethernet.error());
  for (std::size_t i = 0; i < 4; ++i) {
    config.ethernet.ip_address[i] = (*ethernet)[i];
    config.ethernet.subnet_mask[i] = (*ethernet)[4 + i];
    config.ethernet.gateway[i] = (*ethernet)[8 + i];
  }
  config.ethernet.node_id = (*ethernet)[12];
  config.ethernet.transparent_tcp_port = (*ethernet)[13];
  auto serial = reader.next("serial", 4);
  if (!serial) return Unexpected(serial.error());
  config.serial = protocol::SerialConfig{(*serial)[0], (*serial)[1], (*serial)[2], (*serial)[3]};
  auto can = reader.next("can", 5);
  if (!can) return Unexpected(can.error());
  config.can = protocol::CanConfig{(*can)[0], (*can)[1], (*can)[2], (*can)[3], (*can)[4]};
  auto filter = reader.next("filter", 1);
  if (!filter) return Unexpected(filter.error());
  if ((*filter)[0] > 1) return Unexpected(FlashError{FlashErrorKind::value_out_of_range, reader.line_number()});
  config.near_field_filter_on = (*filter)[0] == 1;
  for (std::uint16_t n = 0; n < kSectorSlots; ++n) {
    auto sector = reader.next("sector", 3);
    if (!sector) return Unexpected(sector.error());
    if ((*sector)[0] != n) return Unexpected(FlashError{FlashErrorKind::malformed_line, reader.line_number()});
    config.sectors[n] = Sector{(*sector)[1], (*sector)[2]};
  }
  auto end = reader.next("end", 0);
  if (!end) return Unexpected(end.error());
  return config;
}

}  // namespace

std::string_view describe(FlashErrorKind kind) {
  switch (kind) {
    case FlashErrorKind::empty: return "flash is empty";
    case FlashErrorKind::bad_magic: return "not an ldoem flash image";
    case FlashErrorKind::unsupported_version: return "unsupported flash format version";
    case FlashErrorKind::malformed_line: return "malformed line";
    case FlashErrorKind::value_out_of_range: return "value out of range";
    case FlashErrorKind::trailing_data: return "data after the end record";
  }
  return "unknown flash error";
}

Bytes serialise_flash_image(const DeviceConfig& config) {
  std::string text;
  text += std::string(kFlashMagic) + ' ' + std::to_string(kFlashFormatVersion) + '\n';
  append_record(text, "global", {config.global.sensor_id, config.global.motor_speed_hz, config.global.angle_step_ticks});
  append_record(text, "interlace", {config.interlace.mode});
  const auto& eth = config.ethernet;
  append_record(text, "ethernet",
                {eth.ip_address[0], eth.ip_address[1], eth.ip_address[2], eth.ip_address[3],
                 eth.subnet_mask[0], eth.subnet_mask[1], eth.subnet_mask[2], eth.subnet_mask[3],
                 eth.gateway[0], eth.gateway[1], eth.gateway[2], eth.gateway[3], eth.node_id,
                 eth.transparent_tcp_port});
  const auto& serial = config.serial;
  append_record(text, "serial", {serial.baud_code, serial.parity, serial.stop_bits, serial.data_bits});
  const auto& can = config.can;
  append_record(text, "can", {can.bitrate_code, can.request_id, can.response_id, can.block_size, can.st_min_ms});
  append_record(text, "filter", {config.near_field_filter_on ? 1u : 0u});
  for (std::size_t n = 0; n < kSectorSlots; ++n) {
    append_record(text, "sector", {static_cast<unsigned>(n), config.sectors[n].function, config.sectors[n].stop_ticks});
  }
  text += "end\n";
  return Bytes(text.begin(), text.end());
}

Expected<DeviceConfig, FlashError> parse_flash_image(ByteView image) {
  if (image.empty()) return Unexpected(FlashError{FlashErrorKind::empty, 0});
  const std::string_view text(reinterpret_cast<const char*>(image.data()), image.size());
  const std::size_t first_end = text.find('\n');
  const std::string_view first = text.substr(0, first_end);
  const std::string_view magic_prefix = "ldoem-flash ";
  if (first_end == std::string_view::npos || first.substr(0, magic_prefix.size()) != magic_prefix) {
    return Unexpected(FlashError{FlashErrorKind::bad_magic, 1});
  }
  if (first.substr(magic_prefix.size()) != std::to_string(kFlashFormatVersion)) {
    return Unexpected(FlashError{FlashErrorKind::unsupported_version, 1});
  }
  auto lines = split_lines(text.substr(first_end + 1));
  if (!lines) {
    return Unexpected(FlashError{lines.error().kind, lines.error().line + 1});
  }
  // Line numbers inside the reader are relative to the second line; shift them back.
  RecordReader reader(std::move(*lines));
  auto config = parse_records(reader);
  if (!config) return Unexpected(FlashError{config.error().kind, config.error().line + 1});
  if (!reader.at_end()) return Unexpected(FlashError{FlashErrorKind::trailing_data, reader.line_number() + 2});
  if (config_issue(*config)) return Unexpected(FlashError{FlashErrorKind::value_out_of_range, 0});
  return config;
}

FlashLoadResult load_flash_or(const FlashStore& store, const DeviceConfig& defaults) {
  const Bytes image = store.load();
  auto parsed = parse_flash_image(image);
  if (parsed) return FlashLoadResult{*parsed, std::nullopt};
  return FlashLoadResult{defaults, parsed.error()};
}

}  // namespace ldoem::control
