// One scenario of scenes/faults/ running in ldoem-emud over TCP, and libldoem handles on it.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "daemon_process.hpp"
#include "ldoem/driver/scanner.hpp"

namespace ldoem::fault_scenarios {

using Clock = std::chrono::steady_clock;

struct RunningScene {
  daemon::test::DaemonProcess daemon;
  Clock::time_point ready_at;  // about device time 0 (real time: --time-scale 1)
  driver::TcpEndpoint endpoint;

  // Seconds of device time since start-up, as the host sees them (a little behind the device).
  double elapsed_s() const { return std::chrono::duration<double>(Clock::now() - ready_at).count(); }
  // Sleeps until elapsed_s() >= seconds.
  void wait_until_s(double seconds) const;
};

// Starts ldoem-emud with `scene` (a path) on TCP, no CAN, no flash file, plus `extra` arguments;
// nothing when it does not come up (the test fails with the daemon's stderr).
std::optional<RunningScene> start_scene(const std::string& scene, const std::vector<std::string>& extra = {},
                                        std::string* failure = nullptr);
std::string scenario(const std::string& name);  // scenes/faults/NAME.yaml

// A Scanner on the scene's TCP endpoint that can reconnect; connected (GET_STATUS answered).
std::unique_ptr<driver::Scanner> connect_scanner(const RunningScene& scene, driver::ScannerOptions options = {});

}  // namespace ldoem::fault_scenarios
