// ldoem-emud's loop (design.md data flow): one epoll loop, the simulated clock (D7) that turns
// deadlines into wall time or jumps over idle time, and the device instances it drives: each is
// a control unit with its plant and its endpoints (device_instance.hpp), or with --replay a
// recorded device (replay_instance.hpp). Which endpoints open
// comes from the options through the endpoint registry (endpoint_registry.hpp). Everything that
// decides something lives in the tested pieces; this class only moves time.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "ldoem/daemon/options.hpp"
#include "ldoem/endpoints/counters.hpp"
#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::control_socket {
class ControlTarget;
}

namespace ldoem::daemon {

class DeviceInstance;

struct StartFailure {
  int exit_code = kExitUsageError;
  std::string message;  // one line: "can: interface vcan0 does not exist"
};

using DaemonCounters = endpoints::Counters;
// Endpoints a test or benchmark adds to scanner i (endpoints::MemoryEndpoint), beside the options'.
using ExtraEndpoints = std::function<std::vector<std::unique_ptr<endpoints::HostEndpoint>>(std::size_t scanner)>;
using endpoints::format_counters;

class Daemon {
 public:
  // Builds the scene's models, loads the flash, opens every endpoint the options name plus
  // `extra_endpoints` (tests: endpoints::MemoryEndpoint), prints one line per endpoint on `out`,
  // then "ready". `log` gets the diagnostics. With several scanners (issue 15) each one's
  // endpoints come from the scene (scanner_options.hpp), a line "scanner NAME" comes before its
  // endpoints' lines, and `extra_endpoints` go to the first.
  static base::Expected<std::unique_ptr<Daemon>, StartFailure> create(
      Options options, scene::Scene scene, std::ostream& out, std::ostream& log,
      std::vector<std::unique_ptr<endpoints::HostEndpoint>> extra_endpoints = {});
  // The same with extra endpoints for every scanner.
  static base::Expected<std::unique_ptr<Daemon>, StartFailure> create_with_endpoints(
      Options options, scene::Scene scene, std::ostream& out, std::ostream& log, const ExtraEndpoints& extra_endpoints);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  // Runs until SIGINT/SIGTERM (128 + signal), --count-profiles or --timeout (0), or a fatal
  // loop error (1). Then flushes the endpoints and saves the flash.
  int run();
  // Runs loop rounds until `done()` holds, the loop stops, or `wall_limit` has passed on the wall
  // clock; returns done(). For tests that drive a MemoryEndpoint between rounds.
  bool run_until(const std::function<bool()>& done, std::chrono::milliseconds wall_limit);

  // Summed over the scanners.
  DaemonCounters counters() const;
  // Issue 15: one device instance per scanner of the scene, in its order (one for `scanner:`).
  std::optional<std::uint16_t> tcp_port(std::size_t scanner = 0) const;
  DeviceInstance& device(std::size_t scanner = 0);
  std::size_t device_count() const;
  // Simulated time now (D7).
  base::SimTime now() const;
  // What the control socket's commands act on (--control, --event-log or scene faults); null
  // otherwise. Tests call control_socket::handle_line on it between loop rounds.
  control_socket::ControlTarget* control_target();

  struct Impl;

 private:
  explicit Daemon(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::daemon
