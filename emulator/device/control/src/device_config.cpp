#include "ldoem/control/device_config.hpp"

#include <type_traits>

namespace ldoem::control {
namespace {

bool in_range(std::uint16_t value, std::uint16_t low, std::uint16_t high) {
  return value >= low && value <= high;
}

bool octets_ok(const std::array<std::uint16_t, 4>& octets) {
  for (const std::uint16_t octet : octets) {
    if (octet > kMaxAddressOctet) return false;
  }
  return true;
}

std::optional<ConfigIssue> interlace_issue(const protocol::InterlaceConfig& interlace) {
  if (interlace.mode > kMaxInterlaceMode) return ConfigIssue::interlace_mode_out_of_range;
  return std::nullopt;
}

}  // namespace

DeviceConfig factory_config() {
  DeviceConfig config;
  config.global = protocol::GlobalConfig{1, 10, 4, false};
  config.ethernet.ip_address = {192, 168, 1, 10};
  config.ethernet.subnet_mask = {255, 255, 255, 0};
  config.ethernet.gateway = {192, 168, 1, 1};
  config.serial = protocol::SerialConfig{6, 0, 1, 8};  // 115200 8N1, S2's setting
  config.can = protocol::CanConfig{4, 0x6C0, 0x6C1, 0, 0};  // D1
  // D4: sector 0 normal to 135 deg, sector 1 blanked to 225 deg, the rest not initialised.
  config.sectors[0] = Sector{static_cast<std::uint16_t>(SectorFunction::normal_measurement), 2160};
  config.sectors[1] = Sector{static_cast<std::uint16_t>(SectorFunction::no_measurement), 3600};
  return config;
}

std::string_view describe(ConfigIssue issue) {
  switch (issue) {
    case ConfigIssue::sensor_id_out_of_range: return "sensor id outside 1..254";
    case ConfigIssue::motor_speed_out_of_range: return "motor speed outside 5..20 Hz";
    case ConfigIssue::angle_step_invalid: return "angle step does not divide 5760 or is below 2 ticks";
    case ConfigIssue::interlace_mode_out_of_range: return "interlace mode out of range";
    case ConfigIssue::interlace_needed_by_angle_step: return "a 1-tick angle step needs interlace on";
    case ConfigIssue::address_octet_out_of_range: return "address octet above 255";
    case ConfigIssue::serial_field_out_of_range: return "RS-232 field out of range";
    case ConfigIssue::can_field_out_of_range: return "CAN field out of range";
    case ConfigIssue::sector_invalid: return "sector entry invalid";
  }
  return "unknown configuration issue";
}

std::optional<ConfigIssue> global_issue(const protocol::GlobalConfig& global,
                                        const protocol::InterlaceConfig& interlace) {
  if (!in_range(global.sensor_id, kMinSensorId, kMaxSensorId)) return ConfigIssue::sensor_id_out_of_range;
  if (!in_range(global.motor_speed_hz, kMinMotorSpeedHz, kMaxMotorSpeedHz)) {
    return ConfigIssue::motor_speed_out_of_range;
  }
  const std::uint16_t step = global.angle_step_ticks;
  if (step == 0 || kTicksPerTurn % step != 0) return ConfigIssue::angle_step_invalid;
  if (step < kMinAngleStepTicks) {
    if (step != kInterlacedAngleStepTicks) return ConfigIssue::angle_step_invalid;
    if (interlace.mode == 0) return ConfigIssue::interlace_needed_by_angle_step;
  }
  return interlace_issue(interlace);
}

std::optional<ConfigIssue> ethernet_issue(const protocol::EthernetConfig& ethernet) {
  if (!octets_ok(ethernet.ip_address) || !octets_ok(ethernet.subnet_mask) || !octets_ok(ethernet.gateway)) {
    return ConfigIssue::address_octet_out_of_range;
  }
  return std::nullopt;  // NODEID and the transparent port have no published bounds
}

std::optional<ConfigIssue> serial_issue(const protocol::SerialConfig& serial) {
  if (!in_range(serial.baud_code, kMinBaudCode, kMaxBaudCode) || serial.parity > kMaxParity ||
      !in_range(serial.stop_bits, kMinStopBits, kMaxStopBits) ||
      !in_range(serial.data_bits, kMinDataBits, kMaxDataBits)) {
    return ConfigIssue::serial_field_out_of_range;
  }
  return std::nullopt;
}

std::optional<ConfigIssue> can_issue(const protocol::CanConfig& can) {
  if (!in_range(can.bitrate_code, kMinCanBitrateCode, kMaxCanBitrateCode) ||
      can.request_id > kMaxCanStandardId || can.response_id > kMaxCanStandardId ||
      can.request_id == can.response_id || can.block_size > kMaxCanBlockSize ||
      can.st_min_ms > kMaxCanStMinMs) {
    return ConfigIssue::can_field_out_of_range;
  }
  return std::nullopt;
}

bool sector_entry_acceptable(const Sector& sector) {
  switch (static_cast<SectorFunction>(sector.function)) {
    case SectorFunction::not_initialised: return true;
    case SectorFunction::no_measurement:
    case SectorFunction::normal_measurement:
    case SectorFunction::reference_measurement: return sector.stop_ticks <= kTicksPerTurn;
    case SectorFunction::reserved: return false;
  }
  return false;  // function > 4
}

std::optional<ConfigIssue> config_issue(const DeviceConfig& config) {
  if (auto issue = global_issue(config.global, config.interlace)) return issue;
  if (auto issue = ethernet_issue(config.ethernet)) return issue;
  if (auto issue = serial_issue(config.serial)) return issue;
  if (auto issue = can_issue(config.can)) return issue;
  for (const Sector& sector : config.sectors) {
    if (!sector_entry_acceptable(sector)) return ConfigIssue::sector_invalid;
  }
  return std::nullopt;
}

std::optional<ConfigIssue> apply_config_body(DeviceConfig& config, const protocol::ConfigBody& body) {
  return std::visit(
      [&config](const auto& value) -> std::optional<ConfigIssue> {
        using Body = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<Body, protocol::GlobalConfig>) {
          if (auto issue = global_issue(value, config.interlace)) return issue;
          config.global = value;
          config.global.trailing_zero_word = false;  // a syntax detail of S2's request, not state
        } else if constexpr (std::is_same_v<Body, protocol::InterlaceConfig>) {
          if (auto issue = global_issue(config.global, value)) return issue;
          config.interlace = value;
        } else if constexpr (std::is_same_v<Body, protocol::EthernetConfig>) {
          if (auto issue = ethernet_issue(value)) return issue;
          config.ethernet = value;
        } else if constexpr (std::is_same_v<Body, protocol::SerialConfig>) {
          if (auto issue = serial_issue(value)) return issue;
          config.serial = value;
        } else {
          static_assert(std::is_same_v<Body, protocol::CanConfig>);
          if (auto issue = can_issue(value)) return issue;
          config.can = value;
        }
        return std::nullopt;
      },
      body);
}

std::optional<protocol::ConfigBody> config_body_for(const DeviceConfig& config, protocol::ConfigKey key) {
  switch (key) {
    case protocol::ConfigKey::serial: return protocol::ConfigBody{config.serial};
    case protocol::ConfigKey::can: return protocol::ConfigBody{config.can};
    case protocol::ConfigKey::ethernet: return protocol::ConfigBody{config.ethernet};
    case protocol::ConfigKey::global: return protocol::ConfigBody{config.global};
    case protocol::ConfigKey::interlace: return protocol::ConfigBody{config.interlace};
    case protocol::ConfigKey::arcnet_historical:
    case protocol::ConfigKey::reserved:
    case protocol::ConfigKey::arcnet: return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace ldoem::control
