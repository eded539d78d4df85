#include "ldoem/plant/scene_device_defaults.hpp"

#include "ldoem/protocol/messages.hpp"

namespace ldoem::plant {
namespace {
std::array<std::uint16_t, 4> widen(const std::array<std::uint8_t, 4>& octets) {
  return {octets[0], octets[1], octets[2], octets[3]};
}
}  // namespace

control::DeviceConfig device_config_from(const scene::FlashDefaults& defaults) {
  control::DeviceConfig config = control::factory_config();
  config.global.sensor_id = defaults.sensor_id;
  config.global.motor_speed_hz = defaults.motor_speed_hz;
  config.global.angle_step_ticks = defaults.angle_step_ticks;
  for (std::size_t i = 0; i < control::kSectorSlots; ++i) {
    config.sectors[i] = control::Sector{defaults.sectors[i].function, defaults.sectors[i].stop_ticks};
  }
  config.ethernet.ip_address = widen(defaults.ip_address);
  config.ethernet.subnet_mask = widen(defaults.subnet_mask);
  config.ethernet.gateway = widen(defaults.gateway);
  config.can.request_id = defaults.can_request_id;
  config.can.response_id = defaults.can_response_id;
  return config;
}

control::IdentificationTexts identification_from(const scene::Identification& identification) {
  namespace item = protocol::ident_item;
  return control::IdentificationTexts{
      {item::kSensorPartNumber, identification.sensor_part_number},
      {item::kSensorName, identification.sensor_name},
      {item::kSensorVersion, identification.sensor_version},
      {item::kSensorSerialNumber, identification.sensor_serial_number},
      {item::kEdmSerialNumber, identification.edm_serial_number},
      {item::kFirmwarePartNumber, identification.firmware_part_number},
      {item::kFirmwareName, identification.firmware_name},
      {item::kFirmwareVersion, identification.firmware_version},
      {item::kApplicationPartNumber, identification.application_part_number},
      {item::kApplicationName, identification.application_name},
      {item::kApplicationVersion, identification.application_version},
  };
}

}  // namespace ldoem::plant
