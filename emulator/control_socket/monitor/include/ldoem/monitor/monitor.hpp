// ldoem-emud's monitor (D11): the daemon's side of the control socket. It owns the control
// server (--control), the event log (--event-log) and one ControlTarget per scanner
// (scanner_target.hpp), and it is the daemon's own target: quit, the D12 object commands
// (object_control.cpp) and the scanner a "scanner" argument names. Every event of the daemon goes
// through publish(): the info log (FAULT_INJECTED), the event log and the server's clients.
// Built only when the scene names faults or --control/--event-log ask (D9).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "ldoem/base/expected.hpp"
#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/control_socket/control_server.hpp"
#include "ldoem/control_socket/object_commands.hpp"
#include "ldoem/endpoints/logger.hpp"
#include "ldoem/endpoints/scheduler.hpp"
#include "ldoem/fault_injection/fault_injector.hpp"
#include "ldoem/monitor/event_log.hpp"
#include "ldoem/monitor/scanner_target.hpp"

namespace ldoem::plant {
class SceneWorld;
}  // namespace ldoem::plant

namespace ldoem::raycast {
class TriMeshData;  // ode_world.hpp: a mesh's collision tree, built by add-object's worker
}  // namespace ldoem::raycast

namespace ldoem::monitor {

class Monitor final : public control_socket::ControlTarget {
 public:
  struct Setup {
    std::optional<std::string> control_path;    // --control
    std::optional<std::string> event_log_path;  // --event-log
    std::string version;
    plant::SceneWorld* world = nullptr;  // for the object commands; must outlive the monitor
    // Without a world, why: the object commands' refusal after "COMMAND: ".
    std::string no_world = "this daemon has no scene world";
    // add-object imports a mesh on a worker thread (issue 27); false under --virtual-time, where
    // the clock stands still while the loop imports, so that runs stay deterministic.
    bool imports_off_loop = false;
    // Issue 15: with several scanners every event names its scanner; with one the lines stay
    // as they were.
    bool several_scanners = false;
  };
  // Opens the event log and the control server. `loop`, `scheduler` and `logger` must outlive
  // the monitor; quit() calls `stop`.
  static base::Expected<std::unique_ptr<Monitor>, std::string> open(io::EventLoop& loop, endpoints::Scheduler& scheduler,
                                                                    const endpoints::Logger& logger, Setup setup,
                                                                    std::function<void()> stop);
  ~Monitor() override;
  Monitor(const Monitor&) = delete;
  Monitor& operator=(const Monitor&) = delete;

  // The next scanner's target, in the scene's order: the first one takes the commands that name
  // no scanner. `faults` (null for a recorded device) and `readings` must outlive the monitor.
  ScannerTarget& add_scanner(std::string name, fault_injection::FaultTap* faults, const DeviceReadings& readings);

  // The event bus: one event of `scanner` (its scene name) to the log, the event log and the
  // clients.
  void publish(std::string_view scanner, fault_injection::InjectorEvent event);

  base::SimTime now() { return scheduler_.now(); }
  std::uint64_t event_log_write_errors() const { return event_log_.write_errors(); }
  std::uint64_t mesh_trees_built_on_loop() const { return mesh_trees_on_loop_; }

  // --- ControlTarget: the fault commands act on the first scanner ---
  control_socket::CommandResult inject_fault(const faults::FaultSpec& spec) override;
  control_socket::CommandResult clear_fault(std::optional<std::uint64_t> id) override;
  nlohmann::json query_faults() override;
  nlohmann::json query_status() override;
  void quit() override { stop_(); }
  ControlTarget* scanner(std::string_view name) override;
  // object_control.cpp: D12 runtime changes through plant::SceneWorld, on the loop's thread.
  control_socket::CommandResult move_object(const nlohmann::json& arguments) override;
  control_socket::CommandResult add_object(const nlohmann::json& arguments) override;
  control_socket::CommandResult remove_object(const nlohmann::json& arguments) override;
  bool add_object_later(const nlohmann::json& arguments, ReplyLine reply_line) override;

 private:
  Monitor(io::EventLoop& loop, endpoints::Scheduler& scheduler, const endpoints::Logger& logger, Setup setup,
          std::function<void()> stop);
  // The daemon's own events (the object commands') go out as the first scanner's.
  void publish_daemon(fault_injection::InjectorEvent event);
  // add-object after its parse (and mesh import): the world change, the event, the reply.
  control_socket::CommandResult add_parsed(const nlohmann::json& arguments,
                                           control_socket::ParsedAddObject parsed,
                                           base::SimTime now, std::shared_ptr<const raycast::TriMeshData> mesh = nullptr);
  void finish_import();
  void abandon_import();  // at destruction: the worker may still run, and owns what it uses

  io::EventLoop& loop_;
  endpoints::Scheduler& scheduler_;
  const endpoints::Logger& logger_;
  std::function<void()> stop_;
  plant::SceneWorld* world_ = nullptr;
  std::string no_world_;
  bool imports_off_loop_ = false;
  bool several_ = false;
  std::unique_ptr<control_socket::ControlServer> server_;
  EventLog event_log_;
  std::vector<std::unique_ptr<ScannerTarget>> scanners_;  // in the scene's order
  std::uint64_t mesh_trees_on_loop_ = 0;  // built by world changes on the loop (query-status)
  struct Import;                          // object_control.cpp: the one mesh import in flight
  std::shared_ptr<Import> import_;
};

}  // namespace ldoem::monitor
