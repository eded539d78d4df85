// The LD's configuration as it lives in RAM and in flash (spec 3.4, 3.6, D1, D4), and the rules
// that say which values SET_CONFIG accepts. Pure values and functions.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "ldoem/control/sector_table.hpp"
#include "ldoem/protocol/config.hpp"

namespace ldoem::control {

// Value ranges (spec 3.4, D1). Where no public source bounds a field the bound is ours and says so.
inline constexpr std::uint16_t kMinSensorId = 1;
inline constexpr std::uint16_t kMaxSensorId = 254;
using base::kMaxMotorSpeedHz;  // spec 6
using base::kMinMotorSpeedHz;
inline constexpr std::uint16_t kMinAngleStepTicks = 2;   // spec 3.4: > 1 tick ...
inline constexpr std::uint16_t kInterlacedAngleStepTicks = 1;  // ... except with interlace (S4)
inline constexpr std::uint16_t kMaxInterlaceMode = 15;  // ours: S4 uses 3; nothing bounds it
inline constexpr std::uint16_t kMaxAddressOctet = 255;
inline constexpr std::uint16_t kMinBaudCode = 1, kMaxBaudCode = 6;  // 4800 .. 115200
inline constexpr std::uint16_t kMaxParity = 2;                      // none, even, odd
inline constexpr std::uint16_t kMinStopBits = 1, kMaxStopBits = 2;
inline constexpr std::uint16_t kMinDataBits = 1, kMaxDataBits = 8;
inline constexpr std::uint16_t kMinCanBitrateCode = 1, kMaxCanBitrateCode = 4;  // D1
inline constexpr std::uint16_t kMaxCanStandardId = 0x7FF;                        // D1: 11-bit
inline constexpr std::uint16_t kMaxCanBlockSize = 255;
inline constexpr std::uint16_t kMaxCanStMinMs = 127;

// Everything the LD keeps per configuration key, plus the sector table and the near-field
// filter (SET_FILTER is stored in flash, spec 3.3). The same struct is the RAM copy and the
// flash copy.
struct DeviceConfig {
  protocol::GlobalConfig global;  // trailing_zero_word always false once stored
  protocol::EthernetConfig ethernet;
  protocol::SerialConfig serial;
  protocol::CanConfig can;
  protocol::InterlaceConfig interlace;
  bool near_field_filter_on = false;
  SectorTable sectors{};
  bool operator==(const DeviceConfig&) const = default;
};

// D4: what the flash holds at first power-up when no scene overrides it (the scene's
// FlashDefaults carry the same values; plant/scene_device_defaults.hpp converts them).
DeviceConfig factory_config();

// Why a configuration value is refused (SET_CONFIG answers 0x0001 for all of them, D2; the
// flash parser names them).
enum class ConfigIssue : std::uint8_t {
  sensor_id_out_of_range,
  motor_speed_out_of_range,
  angle_step_invalid,  // does not divide 5760, or below 2 ticks without interlace
  interlace_mode_out_of_range,
  interlace_needed_by_angle_step,  // interlace 0 while the step is 1 tick
  address_octet_out_of_range,
  serial_field_out_of_range,
  can_field_out_of_range,
  sector_invalid,  // see sector_issue()
};

std::string_view describe(ConfigIssue issue);

// Each returns nothing when the value is acceptable. The global and interlace checks need the
// other key, because a 1-tick step is allowed only while interlace is on (S4).
std::optional<ConfigIssue> global_issue(const protocol::GlobalConfig& global,
                                        const protocol::InterlaceConfig& interlace);
std::optional<ConfigIssue> ethernet_issue(const protocol::EthernetConfig& ethernet);
std::optional<ConfigIssue> serial_issue(const protocol::SerialConfig& serial);
std::optional<ConfigIssue> can_issue(const protocol::CanConfig& can);

// SET_FUNCTION's acceptance rule for one sector (spec 3.6, lead decision): function 0, 1, 3 or
// 4, and stop <= 5760 unless the function is 0 (S2 sends 0xFFF0 there and the LD took it).
bool sector_entry_acceptable(const Sector& sector);

// The whole configuration, as the flash parser checks it.
std::optional<ConfigIssue> config_issue(const DeviceConfig& config);

// Writes one SET_CONFIG body into `config` if acceptable together with the rest of `config`;
// returns the issue otherwise and leaves `config` unchanged.
std::optional<ConfigIssue> apply_config_body(DeviceConfig& config, const protocol::ConfigBody& body);

// The body GET_CONFIG answers for `key`; nothing for a key without a layout.
std::optional<protocol::ConfigBody> config_body_for(const DeviceConfig& config, protocol::ConfigKey key);

}  // namespace ldoem::control
