#include "ldoem/daemon/daemon.hpp"

#include <algorithm>
#include <csignal>
#include <cstring>
#include <iterator>
#include <new>
#include <stdexcept>

#include <pthread.h>
#include <systemd/sd-daemon.h>

#include "ldoem/daemon/device_instance.hpp"
#include "ldoem/daemon/endpoint_registry.hpp"
#include "ldoem/daemon/flash_start.hpp"
#include "ldoem/daemon/replay_instance.hpp"
#include "ldoem/daemon/scanner_options.hpp"
#include "ldoem/daemon/sim_clock.hpp"
#include "ldoem/daemon/supervision.hpp"
#include "ldoem/endpoints/tcp_endpoint.hpp"
#include "ldoem/io/event_loop.hpp"
#include "ldoem/plant/scene_plant.hpp"
#include "ldoem/scene/scanners.hpp"

namespace ldoem::daemon {

using base::SimTime;
using base::Unexpected;

namespace {

// With nothing to simulate, a virtual-time daemon waits this long for a host per round.
constexpr std::chrono::milliseconds kVirtualIdleWait{50};
// SIGINT/SIGTERM stop the loop (exit 128 + N), SIGUSR1 dumps the counters.
constexpr int kHandledSignals[] = {SIGINT, SIGTERM, SIGUSR1};
// With --virtual-time, a deadline that waits for a host (ISO-TP N_Bs/N_Cr, D1) is only jumped to
// after the host has been silent this long on the wall clock: a real host needs wall time to answer.
constexpr std::chrono::seconds kVirtualHostGrace{1};

}  // namespace

struct Daemon::Impl final : endpoints::Scheduler {
  Options options;
  scene::Scene scene;
  std::ostream& out;
  std::ostream& log;  // the logger's stream; a replayed device's report (replay_instance.hpp)
  endpoints::Logger logger;
  std::unique_ptr<io::EventLoop> loop;
  SimClock clock = SimClock::virtual_clock();
  DeadlineQueue deadlines;
  std::optional<io::EventLoop::TimerId> wall_timer;
  std::optional<SimTime> wall_timer_for;

  std::unique_ptr<plant::SceneWorld> world;  // shared by the device instances
  // Issue 15: with several scanners, what each device reads of the scene (scanner_view); with
  // one, the device reads `scene` itself. Declared before the devices, which keep references.
  std::vector<std::unique_ptr<scene::Scene>> views;
  std::vector<std::unique_ptr<DeviceInstance>> devices;  // one per scanner, in the scene's order
  // D11: only when the scene names faults or --control/--event-log ask (D9: nothing otherwise).
  // Declared after the devices: its taps plug into them and go first.
  std::unique_ptr<Supervision> supervision;

  std::uint64_t activity = 0;  // fd callbacks that did something (virtual time: is anything ready?)
  WallTime last_activity_wall{};
  std::optional<int> stop_signal;
  bool fatal = false;

  Impl(Options options_in, scene::Scene scene_in, std::ostream& out_in, std::ostream& log_in)
      : options(std::move(options_in)), scene(std::move(scene_in)), out(out_in), log(log_in),
        logger(log_in, options.log_level) {}

  // --- Scheduler (the endpoints' and the device's view of time) ---
  SimTime now() override { return clock.now(io::EventLoop::now()); }
  SimTime at_wall_time(WallTime wall) override { return clock.now(wall); }
  Key add(SimTime at, Action action) override { return deadlines.add(at, std::move(action)); }
  void cancel(const Key& key) override { deadlines.cancel(key); }

  std::optional<StartFailure> build_devices(const ExtraEndpoints& extra);
  std::optional<StartFailure> build_device(const Options& device_options, const scene::Scene& view,
                                           std::optional<std::uint32_t> own_housing);
  std::optional<StartFailure> open_device(std::size_t index, const Options& device_options, const scene::Scene& view,
                                          std::vector<std::unique_ptr<endpoints::HostEndpoint>> extra);
  std::uint64_t profiles_sent() const {
    std::uint64_t sent = 0;
    for (const auto& device : devices) sent += device->model().diagnostics().profiles_sent;
    return sent;
  }
  bool waiting_for_host() const {
    return std::any_of(devices.begin(), devices.end(), [](const auto& device) { return device->waiting_for_host(); });
  }
  std::optional<StartFailure> build_faults();
  void fire_due(SimTime at);
  void arm_wall_timer();
  void after_event();
  bool round();
  void on_signal(int signal_number);
  endpoints::Counters counters() const;
  void fail(const io::IoError& error) {
    logger.log(endpoints::LogLevel::error, error.message());
    fatal = true;
  }
};

std::optional<StartFailure> Daemon::Impl::build_devices(const ExtraEndpoints& extra) {
  auto per_scanner = scanner_options(options, scene);
  if (!per_scanner) return StartFailure{kExitUsageError, per_scanner.error().message};
  if (options.seed) {
    scene.seed = *options.seed;
  }
  // Issue 15: with two scanners or more, each one's housing is geometry the others see.
  const std::vector<std::uint32_t> housings = scene::add_housings(scene);
  // With a control socket objects may be added, removed and moved (D12 runtime changes).
  world = std::make_unique<plant::SceneWorld>(scene, options.control_path.has_value());
  auto created = io::EventLoop::create();
  if (!created) {
    return StartFailure{kExitRuntimeFailure, created.error().message()};
  }
  loop = std::move(*created);
  if (auto watched = loop->on_signals(std::vector<int>(std::begin(kHandledSignals), std::end(kHandledSignals)),
                                      [this](int number) { on_signal(number); });
      !watched) {
    return StartFailure{kExitRuntimeFailure, watched.error().message()};
  }
  const std::size_t count = per_scanner->size();
  for (std::size_t i = 0; i < count; ++i) {
    if (count > 1) views.push_back(std::make_unique<scene::Scene>(scene::scanner_view(scene, i)));
    const scene::Scene& view = count > 1 ? *views.back() : scene;
    const std::optional<std::uint32_t> own_housing = housings.empty() ? std::nullopt : std::optional(housings[i]);
    if (auto failure = build_device((*per_scanner)[i], view, own_housing)) return failure;
    if (count > 1) out << "scanner " << scene::scanner_name(scene, i) << "\n";
    auto failure = open_device(i, (*per_scanner)[i], view,
                               extra ? extra(i) : std::vector<std::unique_ptr<endpoints::HostEndpoint>>{});
    if (failure) return failure;
  }
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::build_device(const Options& device_options, const scene::Scene& view,
                                                       std::optional<std::uint32_t> own_housing) {
  if (device_options.replay_path) {  // --replay: a recorded device, no plant, no flash
    auto replayed = replay_instance(device_options, *this, logger, log);
    if (!replayed) return std::move(replayed.error());
    devices.push_back(std::move(*replayed));
    return std::nullopt;
  }
  auto flash = start_flash(device_options, options.reset_flash, view, logger);
  if (!flash) return std::move(flash.error());
  devices.push_back(
      std::make_unique<DeviceInstance>(view, *world, std::move(flash->store), flash->config, *this, logger, own_housing));
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::open_device(std::size_t index, const Options& device_options,
                                                      const scene::Scene& view,
                                                      std::vector<std::unique_ptr<endpoints::HostEndpoint>> extra) {
  DeviceInstance& device = *devices.at(index);
  const DeviceFacts facts{device.can_config(), view};
  for (const EndpointEntry& entry : endpoint_registry()) {
    if (auto endpoint = entry.make(device_options, facts)) device.add_endpoint(std::move(endpoint));
  }
  for (auto& endpoint : extra) device.add_endpoint(std::move(endpoint));
  if (!device.has_host_transport()) return StartFailure{kExitUsageError, no_host_transport_error(scene, index)};
  if (auto failure = device.open_endpoints(*loop, out, activity)) {
    return StartFailure{failure->usage_error ? kExitUsageError : kExitRuntimeFailure, failure->message};
  }
  return std::nullopt;
}

endpoints::Counters Daemon::Impl::counters() const {
  endpoints::Counters all;
  for (const auto& device : devices) all += device->counters();
  if (supervision) supervision->fill_counters(all);
  return all;
}

std::optional<StartFailure> Daemon::Impl::build_faults() {
  if (scene.faults.empty() && !options.control_path && !options.event_log_path) return std::nullopt;
  auto built = Supervision::create(scene, devices, options, world.get(), *this, *loop, logger, [this] { loop->stop(); });
  if (!built) return StartFailure{kExitUsageError, built.error()};
  supervision = std::move(*built);
  if (options.control_path) out << "control " << options.control_path->string() << "\n";
  return std::nullopt;
}

void Daemon::Impl::fire_due(SimTime at) {
  while (auto entry = deadlines.pop_due(at)) {
    entry->second(at);
  }
}

void Daemon::Impl::arm_wall_timer() {
  const std::optional<SimTime> earliest = deadlines.earliest();
  if (earliest == wall_timer_for) return;
  if (wall_timer) {
    loop->cancel_timer(*wall_timer);
    wall_timer.reset();
  }
  wall_timer_for = earliest;
  if (!earliest) return;
  wall_timer = loop->add_timer_at(clock.wall_deadline(*earliest, io::EventLoop::now()), [this, due = *earliest] {
    wall_timer.reset();
    wall_timer_for.reset();
    clock.advance_to(due);  // the wall deadline is rounded up; never let rounding make it early
    fire_due(now());
    after_event();
  });
}

void Daemon::Impl::after_event() {
  if (options.count_profiles && profiles_sent() >= *options.count_profiles) {
    loop->stop();
  }
  if (!clock.is_virtual()) {
    arm_wall_timer();
  }
}

// One loop round; false after a fatal loop error.
bool Daemon::Impl::round() {
  if (!clock.is_virtual()) {
    // Every fd callback ends in the control unit; re-arm after each loop round.
    after_event();
    if (auto status = loop->run_once(std::chrono::seconds(1)); !status) {
      fail(status.error());
      return false;
    }
    return true;
  }
  const std::uint64_t before = activity;
  if (auto status = loop->run_once(std::chrono::nanoseconds::zero()); !status) {
    fail(status.error());
    return false;
  }
  fire_due(now());
  if (activity != before) {
    last_activity_wall = io::EventLoop::now();
  } else if (!loop->stop_requested()) {
    const bool host_grace = waiting_for_host() && io::EventLoop::now() - last_activity_wall < kVirtualHostGrace;
    if (const auto earliest = deadlines.earliest(); earliest && !host_grace) {
      clock.advance_to(*earliest);  // D7 virtual clock: nothing is ready, jump ahead
      fire_due(now());
    } else if (auto status = loop->run_once(kVirtualIdleWait); !status) {
      fail(status.error());
      return false;
    }
    // A host heard during the idle wait is activity too: without this, a request that arrived
    // there started its reply's N_Bs wait with an old last_activity_wall, and the clock jumped
    // over the host's flow control at once (D1 send failure).
    if (activity != before) last_activity_wall = io::EventLoop::now();
  }
  after_event();
  return true;
}

void Daemon::Impl::on_signal(int signal_number) {
  if (signal_number == SIGUSR1) {
    // Asked for: shown at every level.
    logger.log(endpoints::LogLevel::error, format_counters(counters()));
    return;
  }
  stop_signal = signal_number;
  loop->stop();
}

// ------------------------------------------------------------------------------------- Daemon

Daemon::Daemon(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Daemon::~Daemon() = default;

base::Expected<std::unique_ptr<Daemon>, StartFailure> Daemon::create(
    Options options, scene::Scene scene, std::ostream& out, std::ostream& log,
    std::vector<std::unique_ptr<endpoints::HostEndpoint>> extra_endpoints) {
  // std::function needs a copyable callable: the endpoints wait in a shared vector.
  auto first = std::make_shared<std::vector<std::unique_ptr<endpoints::HostEndpoint>>>(std::move(extra_endpoints));
  return create_with_endpoints(std::move(options), std::move(scene), out, log, [first](std::size_t scanner) {
    return scanner == 0 ? std::move(*first) : std::vector<std::unique_ptr<endpoints::HostEndpoint>>{};
  });
}

base::Expected<std::unique_ptr<Daemon>, StartFailure> Daemon::create_with_endpoints(
    Options options, scene::Scene scene, std::ostream& out, std::ostream& log, const ExtraEndpoints& extra_endpoints) {
  // Block the daemon's signals before any thread exists (Embree and TBB start workers while the
  // scene is built): threads inherit the mask, so the signals reach only the loop's signalfd and
  // never kill the process before the flash is saved.
  sigset_t handled;
  sigemptyset(&handled);
  for (const int number : kHandledSignals) sigaddset(&handled, number);
  if (const int error = ::pthread_sigmask(SIG_BLOCK, &handled, nullptr); error != 0) {
    return Unexpected(StartFailure{kExitRuntimeFailure, std::string("pthread_sigmask: ") + std::strerror(error)});
  }
  // Building the world allocates the scene's acceleration structures (Embree, ODE): out of
  // memory, or an Embree error, is a start failure with a message (exit 1), never an abort.
  try {
    auto impl = std::make_unique<Impl>(std::move(options), std::move(scene), out, log);
    if (auto failure = impl->build_devices(extra_endpoints)) return Unexpected(std::move(*failure));
    // Simulated time 0 = power-up (D4) = the moment the endpoints are open.
    impl->clock = impl->options.virtual_time ? SimClock::virtual_clock()
                                             : SimClock::scaled(io::EventLoop::now(), impl->options.time_scale);
    if (auto failure = impl->build_faults()) return Unexpected(std::move(*failure));
    out << "ready" << std::endl;
    return std::unique_ptr<Daemon>(new Daemon(std::move(impl)));
  } catch (const std::bad_alloc&) {
    return Unexpected(StartFailure{kExitRuntimeFailure, "out of memory while building the scene"});
  } catch (const std::exception& error) {
    return Unexpected(StartFailure{kExitRuntimeFailure, std::string("cannot build the scene: ") + error.what()});
  }
}

namespace {

// Under systemd (Type=notify, WatchdogSec=) the loop itself pings at half the watchdog period,
// so a loop that hangs gets restarted. Outside systemd sd_watchdog_enabled() is 0.
void ping_watchdog(io::EventLoop& loop, std::chrono::microseconds every) {
  sd_notify(0, "WATCHDOG=1");
  loop.add_timer_after(every, [&loop, every] { ping_watchdog(loop, every); });
}

}  // namespace

int Daemon::run() {
  Impl& d = *impl_;
  sd_notify(0, "READY=1");
  if (std::uint64_t watchdog_us = 0; sd_watchdog_enabled(0, &watchdog_us) > 0) {
    ping_watchdog(*d.loop, std::chrono::microseconds(watchdog_us / 2));
  }
  if (d.options.timeout_s) {
    d.loop->add_timer_after(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(*d.options.timeout_s)),
        [&d] { d.loop->stop(); });
  }
  while (!d.loop->stop_requested() && d.round()) {
  }
  sd_notify(0, "STOPPING=1");
  // Every device's flash is tried; one lost flash makes the exit a failure, even after SIGTERM
  // (the services' SuccessExitStatus=143 would otherwise hide it).
  bool every_flash_saved = true;
  for (const auto& device : d.devices) every_flash_saved = device->close() && every_flash_saved;
  d.logger.log(endpoints::LogLevel::info, format_counters(d.counters()));
  if (!every_flash_saved) return kExitRuntimeFailure;
  if (d.stop_signal) return kExitSignalBase + *d.stop_signal;
  return d.fatal ? kExitRuntimeFailure : kExitOk;
}

bool Daemon::run_until(const std::function<bool()>& done, std::chrono::milliseconds wall_limit) {
  const WallTime give_up = io::EventLoop::now() + wall_limit;
  while (!done() && !impl_->loop->stop_requested() && io::EventLoop::now() < give_up && impl_->round()) {
  }
  return done();
}

DaemonCounters Daemon::counters() const { return impl_->counters(); }

std::optional<std::uint16_t> Daemon::tcp_port(std::size_t scanner) const {
  if (scanner >= impl_->devices.size()) return std::nullopt;
  const auto* tcp = dynamic_cast<const endpoints::TcpHostEndpoint*>(impl_->devices[scanner]->endpoint("tcp"));
  return tcp != nullptr ? tcp->port() : std::nullopt;
}

DeviceInstance& Daemon::device(std::size_t scanner) { return *impl_->devices.at(scanner); }
std::size_t Daemon::device_count() const { return impl_->devices.size(); }

SimTime Daemon::now() const { return impl_->now(); }

control_socket::ControlTarget* Daemon::control_target() {
  return impl_->supervision ? &impl_->supervision->control_target() : nullptr;
}

}  // namespace ldoem::daemon
