#include "ldoem/control/identification.hpp"

#include "ldoem/protocol/messages.hpp"

#ifndef LDOEM_VERSION
#define LDOEM_VERSION "0.0.0"
#endif

namespace ldoem::control {

IdentificationTexts default_identification() {
  namespace item = protocol::ident_item;
  const std::string unknown_number = "0000000";
  return IdentificationTexts{
      {item::kSensorPartNumber, unknown_number},     {item::kSensorName, "LD-OEM1000"},
      {item::kSensorVersion, unknown_number},        {item::kSensorSerialNumber, unknown_number},
      {item::kEdmSerialNumber, unknown_number},      {item::kFirmwarePartNumber, unknown_number},
      {item::kFirmwareName, "ldoem-emud"},           {item::kFirmwareVersion, LDOEM_VERSION},
      {item::kApplicationPartNumber, unknown_number}, {item::kApplicationName, unknown_number},
      {item::kApplicationVersion, unknown_number},
  };
}

}  // namespace ldoem::control
