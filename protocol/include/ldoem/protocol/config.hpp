// Configuration key bodies of SET_CONFIG / GET_CONFIG (spec 3.4, D1 for the CAN key).
// Values are kept raw: whether a speed or an address is acceptable is the emulator's decision.
#pragma once

#include <array>
#include <cstdint>
#include <variant>

namespace ldoem::protocol {

enum class ConfigKey : std::uint16_t {
  arcnet_historical = 0x0000,  // layout unpublished
  serial = 0x0001,             // RS-232 / RS-422
  can = 0x0002,                // layout ours (D1)
  reserved = 0x0003,
  arcnet = 0x0004,  // layout unpublished
  ethernet = 0x0005,
  global = 0x0010,
  interlace = 0x0011,  // S4 only
};

// Key 0x0001, spec 3.4: BAUD PARITY STOPBITS DATABITS, each a WORD.
struct SerialConfig {
  static constexpr ConfigKey kKey = ConfigKey::serial;
  std::uint16_t baud_code = 6;  // 1 = 4800 ... 6 = 115200
  std::uint16_t parity = 0;     // 0 none, 1 even, 2 odd
  std::uint16_t stop_bits = 1;
  std::uint16_t data_bits = 8;
  bool operator==(const SerialConfig&) const = default;
};

// Key 0x0002, our layout (D1): BITRATE REQUEST_ID RESPONSE_ID BLOCKSIZE STMIN.
struct CanConfig {
  static constexpr ConfigKey kKey = ConfigKey::can;
  std::uint16_t bitrate_code = 4;  // 1 = 125k, 2 = 250k, 3 = 500k, 4 = 1M
  std::uint16_t request_id = 0x6C0;
  std::uint16_t response_id = 0x6C1;
  std::uint16_t block_size = 0;
  std::uint16_t st_min_ms = 0;
  bool operator==(const CanConfig&) const = default;
};

// Key 0x0005, spec 3.4: every address octet takes a whole WORD.
struct EthernetConfig {
  static constexpr ConfigKey kKey = ConfigKey::ethernet;
  std::array<std::uint16_t, 4> ip_address{};
  std::array<std::uint16_t, 4> subnet_mask{};
  std::array<std::uint16_t, 4> gateway{};
  std::uint16_t node_id = 0;
  std::uint16_t transparent_tcp_port = 0;
  bool operator==(const EthernetConfig&) const = default;
};

// Key 0x0010, spec 3.4: SENSORID MOTORSPEED ANGLESTEP. S2 sends one extra 0x0000 WORD, which is
// accepted (D2) and remembered so that the telegram re-encodes byte for byte.
struct GlobalConfig {
  static constexpr ConfigKey kKey = ConfigKey::global;
  std::uint16_t sensor_id = 1;
  std::uint16_t motor_speed_hz = 10;
  std::uint16_t angle_step_ticks = 4;  // 1/16 degree
  bool trailing_zero_word = false;     // S2's fifth parameter WORD
  bool operator==(const GlobalConfig&) const = default;
};

// Key 0x0011 (S4): MODE, k meaning k+1 interlaced revolutions.
struct InterlaceConfig {
  static constexpr ConfigKey kKey = ConfigKey::interlace;
  std::uint16_t mode = 0;
  bool operator==(const InterlaceConfig&) const = default;
};

using ConfigBody = std::variant<SerialConfig, CanConfig, EthernetConfig, GlobalConfig, InterlaceConfig>;

ConfigKey key_of(const ConfigBody& body);

// True for the keys above that have a layout (and so a ConfigBody alternative).
bool has_config_layout(std::uint16_t key);

}  // namespace ldoem::protocol
