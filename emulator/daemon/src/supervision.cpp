#include "ldoem/daemon/supervision.hpp"

#include <chrono>

#include "ldoem/fault_injection/fault_tap.hpp"
#include "ldoem/monitor/monitor.hpp"

namespace ldoem::daemon {

// One scanner: its device as the tap and the monitor see it, and its tap (none for a recorded
// device: the FaultInjector acts on a control unit).
struct Supervision::Scanner final : fault_injection::FaultedDevice, monitor::DeviceReadings {
  explicit Scanner(DeviceInstance& device_in) : device(device_in) {}
  ~Scanner() override { device.set_connection_observer(nullptr); }  // then the tap unplugs itself

  // --- FaultedDevice ---
  control::ControlUnit& control_unit() override { return device.unit_for_faults(); }
  void perform_actions(base::SimTime at, const control::Actions& actions) override { device.perform_actions(at, actions); }
  void set_power(endpoints::DevicePower power) override { device.set_power(power); }
  void send_to_host(protocol::ConnectionId to, protocol::ByteView payload, bool is_profile) override {
    device.send_to_host(to, payload, is_profile);
  }
  void disconnect(protocol::ConnectionId connection) override { device.disconnect(connection); }
  void set_wire_tap(endpoints::WireTap* tap) override { device.set_wire_tap(tap); }
  endpoints::WireTap* wire_tap() const override { return device.wire_tap(); }
  void set_fault_hook(endpoints::WireFaultHook* hook) override { device.set_fault_hook(hook); }

  // --- DeviceReadings ---
  const control::ControlUnit* unit() const override { return device.control_unit(); }
  endpoints::Counters counters() const override { return device.counters(); }
  std::uint64_t tilt_steps() const override { return device.steps_seen(); }

  DeviceInstance& device;
  std::unique_ptr<fault_injection::FaultTap> tap;
};

Supervision::~Supervision() = default;

control_socket::ControlTarget& Supervision::control_target() { return *monitor_; }

base::Expected<std::unique_ptr<Supervision>, std::string> Supervision::create(
    const scene::Scene& scene, const std::vector<std::unique_ptr<DeviceInstance>>& devices, const Options& options,
    plant::SceneWorld* world, endpoints::Scheduler& scheduler, io::EventLoop& loop, const endpoints::Logger& logger,
    std::function<void()> stop) {
  std::unique_ptr<Supervision> made(new Supervision());
  monitor::Monitor::Setup setup;
  if (options.control_path) setup.control_path = options.control_path->string();
  if (options.event_log_path) setup.event_log_path = options.event_log_path->string();
  setup.version = LDOEM_VERSION;
  // --replay: the daemon's world is an empty scene nobody looks at; the object commands say why
  // they cannot act instead of changing it.
  setup.world = options.replay_path ? nullptr : world;
  if (options.replay_path) setup.no_world = std::string(monitor::kNotForRecorded);
  setup.imports_off_loop = !options.virtual_time;  // issue 27: a stopped virtual clock keeps imports deterministic
  setup.several_scanners = devices.size() > 1;
  auto opened = monitor::Monitor::open(loop, scheduler, logger, std::move(setup), std::move(stop));
  if (!opened) return base::Unexpected(opened.error());
  made->monitor_ = std::move(*opened);
  monitor::Monitor& monitor = *made->monitor_;
  const auto seconds = [](double s) { return std::chrono::duration_cast<base::SimTime>(std::chrono::duration<double>(s)); };
  for (std::size_t k = 0; k < devices.size() && (k == 0 || k < scene.scanners.size()); ++k) {
    // The scene's faults are the first scanner's; scanner k draws with the seed + k, as its
    // noise does (docs/scenes.md).
    fault_injection::FaultTapSetup faults;
    std::string name;
    if (k == 0) {
      faults = {scene.faults, scene.seed, scene.effects.has(scene::Effect::head_dynamics), seconds(scene.scanner.boot_s)};
      if (!scene.scanners.empty()) name = scene.scanners.front().name;
    } else {
      const auto& entry = scene.scanners[k];
      faults = {{}, scene.seed + k, entry.effects.has(scene::Effect::head_dynamics), seconds(entry.config.boot_s)};
      name = entry.name;
    }
    auto scanner = std::make_unique<Scanner>(*devices[k]);
    // A recorded device (--replay) has no control unit for the injector to act on: no tap, and
    // its target answers the fault commands with an error (docs/replay.md).
    if (scanner->device.control_unit() != nullptr) {
      scanner->tap = std::make_unique<fault_injection::FaultTap>(
          *scanner, scheduler, logger, std::move(faults),
          [&monitor, name](const fault_injection::InjectorEvent& event) { monitor.publish(name, event); });
    }
    fault_injection::FaultTap* tap = scanner->tap.get();
    monitor::ScannerTarget& target = monitor.add_scanner(name, tap, *scanner);
    scanner->device.set_connection_observer(
        [tap, &target](bool opened_now, protocol::ConnectionId connection, std::string_view peer) {
          if (!opened_now && tap != nullptr) tap->forget_delayed(connection);
          target.on_connection(opened_now, connection, peer);
        });
    made->scanners_.push_back(std::move(scanner));
  }
  return made;
}

void Supervision::fill_counters(endpoints::Counters& counters) const {
  counters.fault_injections = 0;
  counters.delayed_replies_dropped = 0;
  for (const auto& scanner : scanners_) {
    if (!scanner->tap) continue;
    counters.fault_injections += scanner->tap->injections();
    counters.delayed_replies_dropped += scanner->tap->delayed_replies_dropped();
  }
  counters.event_log_write_errors = monitor_->event_log_write_errors();
}

}  // namespace ldoem::daemon
