#include "ldoem/protocol/config.hpp"

#include <type_traits>

#include "config_codec.hpp"

namespace ldoem::protocol {

ConfigKey key_of(const ConfigBody& body) {
  return std::visit([](const auto& fields) { return std::decay_t<decltype(fields)>::kKey; }, body);
}

bool has_config_layout(std::uint16_t key) {
  switch (static_cast<ConfigKey>(key)) {
    case ConfigKey::serial:
    case ConfigKey::can:
    case ConfigKey::ethernet:
    case ConfigKey::global:
    case ConfigKey::interlace:
      return true;
    case ConfigKey::arcnet_historical:
    case ConfigKey::reserved:
    case ConfigKey::arcnet:
      return false;
  }
  return false;
}

namespace detail {
namespace {

constexpr std::size_t kSerialWords = 4;
constexpr std::size_t kCanWords = 5;
constexpr std::size_t kEthernetWords = 14;
constexpr std::size_t kGlobalWords = 3;
constexpr std::size_t kInterlaceWords = 1;

void append_words(Bytes& out, std::initializer_list<std::uint16_t> words) {
  for (const auto word : words) append_word_be(out, word);
}

void append_fields(Bytes& out, const SerialConfig& c) {
  append_words(out, {c.baud_code, c.parity, c.stop_bits, c.data_bits});
}
void append_fields(Bytes& out, const CanConfig& c) {
  append_words(out, {c.bitrate_code, c.request_id, c.response_id, c.block_size, c.st_min_ms});
}
void append_fields(Bytes& out, const EthernetConfig& c) {
  for (const auto octet : c.ip_address) append_word_be(out, octet);
  for (const auto octet : c.subnet_mask) append_word_be(out, octet);
  for (const auto octet : c.gateway) append_word_be(out, octet);
  append_words(out, {c.node_id, c.transparent_tcp_port});
}
void append_fields(Bytes& out, const GlobalConfig& c) {
  append_words(out, {c.sensor_id, c.motor_speed_hz, c.angle_step_ticks});
  if (c.trailing_zero_word) append_word_be(out, 0x0000);
}
void append_fields(Bytes& out, const InterlaceConfig& c) { append_word_be(out, c.mode); }

std::array<std::uint16_t, 4> read_octets(WordReader& reader) {
  return {reader.word(), reader.word(), reader.word(), reader.word()};
}

}  // namespace

void append_config_body(Bytes& out, const ConfigBody& body) {
  append_word_be(out, static_cast<std::uint16_t>(key_of(body)));
  std::visit([&out](const auto& fields) { append_fields(out, fields); }, body);
}

base::Expected<ConfigBody, DecodeError> read_config_fields(std::uint16_t key, WordReader& reader,
                                                     bool allow_global_zero_pad) {
  if (!has_config_layout(key)) return base::Unexpected(DecodeError::unknown_config_key);
  if (reader.remaining_bytes() % 2 != 0) return base::Unexpected(DecodeError::bad_length);
  const std::size_t words = reader.remaining_words();
  switch (static_cast<ConfigKey>(key)) {
    case ConfigKey::serial: {
      if (words != kSerialWords) return base::Unexpected(DecodeError::bad_length);
      SerialConfig c;
      c.baud_code = reader.word();
      c.parity = reader.word();
      c.stop_bits = reader.word();
      c.data_bits = reader.word();
      return ConfigBody{c};
    }
    case ConfigKey::can: {
      if (words != kCanWords) return base::Unexpected(DecodeError::bad_length);
      CanConfig c;
      c.bitrate_code = reader.word();
      c.request_id = reader.word();
      c.response_id = reader.word();
      c.block_size = reader.word();
      c.st_min_ms = reader.word();
      return ConfigBody{c};
    }
    case ConfigKey::ethernet: {
      if (words != kEthernetWords) return base::Unexpected(DecodeError::bad_length);
      EthernetConfig c;
      c.ip_address = read_octets(reader);
      c.subnet_mask = read_octets(reader);
      c.gateway = read_octets(reader);
      c.node_id = reader.word();
      c.transparent_tcp_port = reader.word();
      return ConfigBody{c};
    }
    case ConfigKey::global: {
      const bool padded = allow_global_zero_pad && words == kGlobalWords + 1;
      if (words != kGlobalWords && !padded) return base::Unexpected(DecodeError::bad_length);
      GlobalConfig c;
      c.sensor_id = reader.word();
      c.motor_speed_hz = reader.word();
      c.angle_step_ticks = reader.word();
      if (padded) {
        if (reader.word() != 0x0000) return base::Unexpected(DecodeError::bad_length);
        c.trailing_zero_word = true;
      }
      return ConfigBody{c};
    }
    case ConfigKey::interlace: {
      if (words != kInterlaceWords) return base::Unexpected(DecodeError::bad_length);
      return ConfigBody{InterlaceConfig{reader.word()}};
    }
    case ConfigKey::arcnet_historical:
    case ConfigKey::reserved:
    case ConfigKey::arcnet:
      break;
  }
  return base::Unexpected(DecodeError::unknown_config_key);
}

}  // namespace detail
}  // namespace ldoem::protocol
