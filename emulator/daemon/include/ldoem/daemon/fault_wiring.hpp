// ldoem-emud's fault machinery (D11), built only when the scene names faults or --control is
// given (D9: a scene without faults pays nothing). It is the device's WireTap: it counts
// requests for the triggers, applies the telegram-level wire faults, and keeps the device silent
// while powered off or booting (its endpoints go dark: DeviceInstance::set_power); and it gives
// the endpoints their fault hook (endpoint_faults.hpp) for the faults below the telegram. It
// drives the FaultInjector from the daemon's simulated clock, serves the control socket and
// writes the event log.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/control_socket/control_server.hpp"
#include "ldoem/control_socket/object_commands.hpp"
#include "ldoem/daemon/device_instance.hpp"
#include "ldoem/daemon/endpoint_faults.hpp"
#include "ldoem/daemon/event_log.hpp"
#include "ldoem/endpoints/scheduler.hpp"
#include "ldoem/base/warning_throttle.hpp"
#include "ldoem/endpoints/wire_tap.hpp"
#include "ldoem/fault_injection/fault_injector.hpp"

namespace ldoem::raycast {
class TriMeshData;  // ode_world.hpp: a mesh's collision tree, built by add-object's worker
}  // namespace ldoem::raycast

namespace ldoem::daemon {

// delay_reply (issue 27 D1): replies held back at once per connection, at most this many and
// this many bytes (64 full-size profiles, as a TCP connection's output queue). Beyond: dropped.
inline constexpr std::size_t kMaxDelayedTelegrams = 64;
inline constexpr std::size_t kMaxDelayedBytes = 64 * 5825;

class FaultWiring final : public endpoints::WireTap, public control_socket::ControlTarget {
 public:
  struct Setup {
    std::optional<std::string> control_path;    // --control
    std::optional<std::string> event_log_path;  // --event-log
    std::string version;
    plant::SceneWorld* world = nullptr;  // for the object commands (object_control.cpp); must outlive it
    // add-object imports a mesh on a worker thread (issue 27); false under --virtual-time, where
    // the clock stands still while the loop imports, so that runs stay deterministic.
    bool imports_off_loop = false;
  };
  // One wiring per device, `devices` in the scene's order (issue 15): the scene's faults, the
  // control socket and the event log belong to the first; the others start without faults and
  // take the fault commands that name them ("scanner"). Each becomes its device's wire tap.
  // `devices`, `scheduler`, `loop` and `logger` must outlive it. quit() calls `stop`.
  static base::Expected<std::unique_ptr<FaultWiring>, std::string> create(
      const scene::Scene& scene, const std::vector<std::unique_ptr<DeviceInstance>>& devices,
      endpoints::Scheduler& scheduler, io::EventLoop& loop, const endpoints::Logger& logger, Setup setup,
      std::function<void()> stop);
  ~FaultWiring() override;

  // --- WireTap ---
  endpoints::WireVerdict on_telegram(endpoints::WireTelegram& telegram) override;

  // --- ControlTarget ---
  control_socket::CommandResult inject_fault(const faults::FaultSpec& spec) override;
  control_socket::CommandResult clear_fault(std::optional<std::uint64_t> id) override;
  nlohmann::json query_faults() override;
  nlohmann::json query_status() override;
  void quit() override;
  ControlTarget* scanner(std::string_view name) override;
  // object_control.cpp: D12 runtime changes through plant::SceneWorld, on the loop's thread.
  control_socket::CommandResult move_object(const nlohmann::json& arguments) override;
  control_socket::CommandResult add_object(const nlohmann::json& arguments) override;
  control_socket::CommandResult remove_object(const nlohmann::json& arguments) override;
  bool add_object_later(const nlohmann::json& arguments, ReplyLine reply_line) override;

  // Every scanner's together.
  std::uint64_t injections() const;
  std::uint64_t delayed_replies_dropped() const;
  // The fault machinery's counters, every scanner's: injections, delayed replies dropped, event
  // log write errors.
  void fill_counters(endpoints::Counters& counters) const {
    counters.fault_injections = injections();
    counters.delayed_replies_dropped = delayed_replies_dropped();
    counters.event_log_write_errors = event_log_.write_errors();
  }

 private:
  FaultWiring(DeviceInstance& device, endpoints::Scheduler& scheduler, const endpoints::Logger& logger,
              std::function<void()> stop);
  // The injector, the endpoints' fault hook and the connection observer of `device_`.
  void attach(std::vector<faults::FaultSpec> scene_faults, std::uint64_t seed, bool head_dynamics, double boot_s);
  void take(fault_injection::InjectorOutput output);
  void publish(const fault_injection::InjectorEvent& event);
  void publish_for(const std::string& scanner, fault_injection::InjectorEvent event);
  void on_connection(bool opened, control::ConnectionId connection, std::string_view peer);
  void arm_deadline();
  // add-object after its parse (and mesh import): the world change, the event, the reply.
  control_socket::CommandResult add_parsed(const nlohmann::json& arguments,
                                           control_socket::ParsedAddObject parsed,
                                           base::SimTime now, std::shared_ptr<const raycast::TriMeshData> mesh = nullptr);
  void finish_import();
  void abandon_import();  // at destruction: the worker may still run, and owns what it uses
  endpoints::WireVerdict to_host(endpoints::WireTelegram& telegram);
  void delay(const endpoints::WireTelegram& telegram, base::SimTime by);
  void release(control::ConnectionId connection, const endpoints::Scheduler::Key& key, std::size_t size);
  void forget_delayed(control::ConnectionId connection);

  DeviceInstance& device_;
  endpoints::Scheduler& scheduler_;
  const endpoints::Logger& logger_;
  std::function<void()> stop_;
  std::unique_ptr<fault_injection::FaultInjector> injector_;
  std::unique_ptr<EndpointFaults> endpoint_faults_;  // the endpoints' fault hook
  std::unique_ptr<control_socket::ControlServer> server_;
  EventLog event_log_;
  std::optional<endpoints::Scheduler::Key> deadline_;
  std::optional<base::SimTime> deadline_at_;
  std::map<control::ConnectionId, std::string> peers_;  // open TCP connections' addresses
  struct DelayedReplies {
    std::set<endpoints::Scheduler::Key> pending;  // deadlines of the held replies
    std::size_t bytes = 0;
  };
  std::map<control::ConnectionId, DelayedReplies> delayed_;  // delay_reply's held replies
  std::uint64_t delayed_dropped_ = 0;
  base::WarningThrottle delayed_warning_{std::chrono::seconds(10)};
  plant::SceneWorld* world_ = nullptr;
  io::EventLoop* loop_ = nullptr;
  bool imports_off_loop_ = false;
  std::uint64_t mesh_trees_on_loop_ = 0;  // built by world changes on the loop (query-status)
  struct Import;                    // object_control.cpp: the one mesh import in flight
  std::shared_ptr<Import> import_;
  std::string name_;                 // the scanner's name in the scene (empty: a scanner: section)
  FaultWiring* first_ = nullptr;     // the first scanner's wiring, which publishes for all; null in it
  bool several_ = false;             // events name their scanner
  std::vector<std::unique_ptr<FaultWiring>> others_;  // the other scanners' (in the first only)
};

}  // namespace ldoem::daemon
