// Each scanner's endpoints and flash, from the command line and the scene (issue 15,
// docs/scenes.md "Several scanners"). A pure function: the daemon opens what it returns.
//
// One scanner (`scanner:`, or a `scanners:` list of one): the command line as always; what it
// does not give, the entry's endpoints and flash_file fill in. Several scanners: every scanner's
// TCP port, CAN identifiers, serial pty, LPT and flash file come from its entry (flash default
// <scene>.<name>.flash); the options that name one device's endpoint (--tcp, --can with ids,
// --serial, --lpt, --flash) and --record are errors; the shared ones (--can/--no-can: one bus for all,
// --no-flash, --virtual-time, --time-scale, --seed, --log-level, --count-profiles: in total,
// --timeout, --control and --event-log: the first scanner) apply to all.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "ldoem/daemon/options.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::daemon {

// One Options per scanner, in the scene's order; the first problem as a one-line usage error.
[[nodiscard]] base::Expected<std::vector<Options>, UsageError> scanner_options(const Options& options,
                                                                                   const scene::Scene& scene);

// The usage error of a scanner that would have no host transport (no CAN, TCP or serial, and no
// extra endpoint): the daemon checks this once the endpoints are made.
[[nodiscard]] std::string no_host_transport_error(const scene::Scene& scene, std::size_t scanner);

}  // namespace ldoem::daemon
