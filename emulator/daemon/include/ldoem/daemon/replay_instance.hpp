// ldoem-emud --replay CAPTURE (docs/replay.md): the device instance of a recorded device
// (emulator/device/replay) instead of a control unit with its plant. Everything else is the
// daemon's: endpoints, scheduler and clock (--time-scale plays the recorded delays faster),
// --record.
#pragma once

#include <memory>

#include "ldoem/base/expected.hpp"
#include "ldoem/daemon/daemon.hpp"
#include "ldoem/daemon/device_instance.hpp"

namespace ldoem::daemon {

// Reads options.replay_path; an unreadable capture, or one without a request on the chosen
// transport, is a usage error naming the file (exit 2). `report` (the logger's stream) gets the
// capture's summary at start and the request counts at exit.
[[nodiscard]] base::Expected<std::unique_ptr<DeviceInstance>, StartFailure> replay_instance(
    const Options& options, endpoints::Scheduler& scheduler, const endpoints::Logger& logger, std::ostream& report);

}  // namespace ldoem::daemon
