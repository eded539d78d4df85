// D11 in the daemon: the faults and the monitor, built only when the scene names faults or
// --control/--event-log ask (D9: a scene without faults pays nothing). The parts live in their
// libraries: each device's FaultTap in emulator/faults, the control server, event log and one
// ControlTarget per scanner in the monitor (emulator/control_socket/monitor). What is left here
// is the construction and the routing between scanners: which device's tap and target belong
// together, whose events name which scanner, and the counters summed over the scanners.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ldoem/base/expected.hpp"
#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/daemon/device_instance.hpp"
#include "ldoem/daemon/options.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::monitor {
class Monitor;
}  // namespace ldoem::monitor

namespace ldoem::daemon {

class Supervision {
 public:
  // One tap and one target per device, `devices` in the scene's order (issue 15): the scene's
  // faults belong to the first; the others start without faults and take the fault commands that
  // name them ("scanner"). The monitor serves --control and writes --event-log of `options`; its
  // object commands change `world`. `devices`, `world`, `scheduler`, `loop` and `logger` must
  // outlive it; quit calls `stop`.
  static base::Expected<std::unique_ptr<Supervision>, std::string> create(
      const scene::Scene& scene, const std::vector<std::unique_ptr<DeviceInstance>>& devices, const Options& options,
      plant::SceneWorld* world, endpoints::Scheduler& scheduler, io::EventLoop& loop, const endpoints::Logger& logger,
      std::function<void()> stop);
  ~Supervision();
  Supervision(const Supervision&) = delete;
  Supervision& operator=(const Supervision&) = delete;

  // What the control socket's commands act on.
  control_socket::ControlTarget& control_target();
  // The fault machinery's counters, every scanner's: injections, delayed replies dropped, event
  // log write errors.
  void fill_counters(endpoints::Counters& counters) const;

 private:
  struct Scanner;  // supervision.cpp: one device's adapter, tap and connection routing
  Supervision() = default;

  std::unique_ptr<monitor::Monitor> monitor_;
  std::vector<std::unique_ptr<Scanner>> scanners_;  // destroyed first: they unplug from the devices
};

}  // namespace ldoem::daemon
