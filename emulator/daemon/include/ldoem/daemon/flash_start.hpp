// D4: a device's flash at start: the store (a file, or memory with --no-flash) and the
// configuration it holds, or the scene's defaults when it holds none.
#pragma once

#include <memory>

#include "ldoem/base/expected.hpp"
#include "ldoem/control/device_config.hpp"
#include "ldoem/control/flash_image.hpp"
#include "ldoem/daemon/daemon.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::daemon {

struct StartedFlash {
  std::unique_ptr<control::FlashStore> store;
  control::DeviceConfig config;
};

// Issue 11: a flash file that exists but cannot be read or parsed stops the start (exit 2): the
// daemon would otherwise run on the scene's defaults and overwrite the file at the first flash
// write or at exit, and whatever it held would be lost. `reset_flash` (--reset-flash) asks for
// exactly that: a warning, and the scene's defaults.
[[nodiscard]] base::Expected<StartedFlash, StartFailure> start_flash(const Options& device_options, bool reset_flash,
                                                                     const scene::Scene& view,
                                                                     const endpoints::Logger& logger);

}  // namespace ldoem::daemon
