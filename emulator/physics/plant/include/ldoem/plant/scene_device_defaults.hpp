// The scene's word on the device (D3 texts, D4 flash defaults) in the control unit's types.
// The only control header that includes the scene model (and so Eigen).
#pragma once

#include "ldoem/control/device_config.hpp"
#include "ldoem/control/identification.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::plant {

// The D4 factory configuration with the scene's values; fields the scene does not describe
// (serial line, interlace, filter, node id, port) keep factory_config()'s.
control::DeviceConfig device_config_from(const scene::FlashDefaults& defaults);

control::IdentificationTexts identification_from(const scene::Identification& identification);

}  // namespace ldoem::plant
