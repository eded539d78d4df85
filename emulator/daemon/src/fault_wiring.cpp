#include "ldoem/daemon/fault_wiring.hpp"

#include <fcntl.h>

#include <algorithm>

#include "ldoem/protocol/isotp.hpp"

namespace ldoem::daemon {

using endpoints::LogLevel;
using protocol::WireDirection;
using endpoints::WireVerdict;
using faults::FaultKind;
using base::SimTime;

namespace {

// The wire faults the tap itself produces (telegram level). The others act inside an endpoint
// through their fault hook (endpoint_faults.hpp): framing, ISO-TP frames, TCP pacing, LPT steps.
constexpr FaultKind kTapKinds[] = {FaultKind::drop_reply, FaultKind::delay_reply, FaultKind::duplicate_reply,
                                   FaultKind::truncate_reply, FaultKind::tcp_reset};

}  // namespace

FaultWiring::FaultWiring(DeviceInstance& device, endpoints::Scheduler& scheduler, const endpoints::Logger& logger,
                         std::function<void()> stop)
    : device_(device), scheduler_(scheduler), logger_(logger), stop_(std::move(stop)) {}

FaultWiring::~FaultWiring() {
  if (deadline_) scheduler_.cancel(*deadline_);
  abandon_import();
  while (!delayed_.empty()) forget_delayed(delayed_.begin()->first);
  device_.set_fault_hook(nullptr);
  device_.set_connection_observer(nullptr);
  if (device_.wire_tap() == this) device_.set_wire_tap(nullptr);
}

base::Expected<std::unique_ptr<FaultWiring>, std::string> FaultWiring::create(
    const scene::Scene& scene, const std::vector<std::unique_ptr<DeviceInstance>>& devices,
    endpoints::Scheduler& scheduler, io::EventLoop& loop, const endpoints::Logger& logger, Setup setup,
    std::function<void()> stop) {
  std::unique_ptr<FaultWiring> wiring(new FaultWiring(*devices.front(), scheduler, logger, stop));
  wiring->world_ = setup.world;
  wiring->loop_ = &loop;
  wiring->imports_off_loop_ = setup.imports_off_loop;
  wiring->several_ = devices.size() > 1;
  if (!scene.scanners.empty()) wiring->name_ = scene.scanners.front().name;
  if (setup.event_log_path) {
    if (auto error = wiring->event_log_.open(*setup.event_log_path)) return base::Unexpected(*error);
  }
  FaultWiring* self = wiring.get();
  if (setup.control_path) {
    auto server = control_socket::ControlServer::open(
        loop, *setup.control_path, control_socket::greeting_line(setup.version),
        [self](std::string_view line) { return control_socket::handle_line(line, *self); });
    if (!server) return base::Unexpected("--control: " + server.error().message());
    wiring->server_ = std::move(*server);
    wiring->server_->set_warning_sink([&logger](const std::string& line) { logger.log(LogLevel::warn, line); });
  }
  wiring->attach(scene.faults, scene.seed, scene.effects.has(scene::Effect::head_dynamics), scene.scanner.boot_s);
  // Scanner k draws with the seed + k, as its noise does (docs/scenes.md).
  for (std::size_t k = 1; k < devices.size() && k < scene.scanners.size(); ++k) {
    std::unique_ptr<FaultWiring> other(new FaultWiring(*devices[k], scheduler, logger, stop));
    other->name_ = scene.scanners[k].name;
    other->first_ = self;
    other->attach({}, scene.seed + k, scene.scanners[k].effects.has(scene::Effect::head_dynamics),
                  scene.scanners[k].config.boot_s);
    wiring->others_.push_back(std::move(other));
  }
  return wiring;
}

void FaultWiring::attach(std::vector<faults::FaultSpec> scene_faults, std::uint64_t seed, bool head_dynamics,
                         double boot_s) {
  injector_ = std::make_unique<fault_injection::FaultInjector>(
      std::move(scene_faults), seed, head_dynamics, device_.unit_for_faults(),
      std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(boot_s)));
  endpoint_faults_ = std::make_unique<EndpointFaults>(
      *injector_, [this](fault_injection::InjectorOutput output) { take(std::move(output)); });
  device_.set_fault_hook(endpoint_faults_.get());
  device_.set_connection_observer([this](bool opened, protocol::ConnectionId connection, std::string_view peer) {
    on_connection(opened, connection, peer);
  });
  device_.set_wire_tap(this);
  take(injector_->advance(scheduler_.now()));
}

std::uint64_t FaultWiring::injections() const {
  std::uint64_t all = injector_->injections();
  for (const auto& other : others_) all += other->injections();
  return all;
}

std::uint64_t FaultWiring::delayed_replies_dropped() const {
  std::uint64_t all = delayed_dropped_;
  for (const auto& other : others_) all += other->delayed_replies_dropped();
  return all;
}

control_socket::ControlTarget* FaultWiring::scanner(std::string_view name) {
  if (name == name_) return this;
  for (const auto& other : others_) {
    if (name == other->name_) return other.get();
  }
  return nullptr;
}

void FaultWiring::publish(const fault_injection::InjectorEvent& event) {
  if (first_ != nullptr) {
    first_->publish_for(name_, event);
  } else {
    publish_for(name_, event);
  }
}

// With several scanners every event names its scanner; with one the lines stay as they were.
void FaultWiring::publish_for(const std::string& scanner, fault_injection::InjectorEvent event) {
  if (several_ && (event.data.is_object() || event.data.is_null())) event.data["scanner"] = scanner;
  const std::string line = control_socket::event_line(event.name, event.data, event.at);
  if (event.name == "FAULT_INJECTED") logger_.log(LogLevel::info, "fault: " + line);  // D11: info level
  if (event_log_.is_open()) {
    // A peer's address (its ephemeral port) differs from run to run: the log leaves it out, so
    // that the same scene, seed and conversation give the same log (D11).
    if (event.data.is_object() && event.data.contains("peer")) {
      nlohmann::json data = event.data;
      data.erase("peer");
      event_log_.write(control_socket::event_line(event.name, data, event.at), logger_);
    } else {
      event_log_.write(line, logger_);
    }
  }
  if (server_) server_->broadcast(line);
}

void FaultWiring::take(fault_injection::InjectorOutput output) {
  if (!output.actions.telegrams.empty() || !output.actions.timers.empty() || output.actions.flash_image) {
    device_.perform_actions(scheduler_.now(), output.actions);
  }
  for (const fault_injection::Power power : output.power_steps) {
    switch (power) {
      case fault_injection::Power::on: device_.set_power(endpoints::DevicePower::on); break;
      case fault_injection::Power::off: device_.set_power(endpoints::DevicePower::off); break;
      case fault_injection::Power::booting: device_.set_power(endpoints::DevicePower::booting); break;
    }
  }
  for (const auto& event : output.events) publish(event);
  arm_deadline();
}

void FaultWiring::arm_deadline() {
  const std::optional<SimTime> next = injector_->next_deadline();
  if (next == deadline_at_) return;
  if (deadline_) scheduler_.cancel(*deadline_);
  deadline_.reset();
  deadline_at_ = next;
  if (!next) return;
  deadline_ = scheduler_.add(*next, [this](SimTime now) {
    deadline_.reset();
    deadline_at_.reset();
    take(injector_->advance(now));
  });
}

WireVerdict FaultWiring::on_telegram(endpoints::WireTelegram& telegram) {
  const protocol::Transport transport = telegram.connection.kind;
  const bool silenced = [&] {
    const faults::ActiveFault* silence = injector_->scheduler().find_active(FaultKind::can_silence);
    return silence && transport == protocol::Transport::can;
  }();
  // Off or booting, the device hears and says nothing (its endpoints are dark as well).
  const bool dark = injector_->power() != fault_injection::Power::on;
  if (telegram.direction == WireDirection::device_to_host) {
    if (dark || silenced) return WireVerdict::drop;
    return to_host(telegram);
  }
  if (dark || silenced) return WireVerdict::drop;
  const std::uint16_t service =
      telegram.payload.size() >= 2 ? static_cast<std::uint16_t>((telegram.payload[0] << 8) | telegram.payload[1]) : 0;
  // A multi-frame ISO-TP request was seen at its first frame already (EndpointFaults).
  const bool came_in_frames = transport == protocol::Transport::can && telegram.payload.size() > protocol::kIsoTpMaxSingleFrameBytes;
  take(injector_->on_request(telegram.at, service, transport,
                             came_in_frames ? faults::RequestSeen::rest_of_multi_frame : faults::RequestSeen::whole));
  if (injector_->power() != fault_injection::Power::on) return WireVerdict::drop;  // a power cycle this very request started
  return WireVerdict::pass;
}

WireVerdict FaultWiring::to_host(endpoints::WireTelegram& telegram) {
  const protocol::Transport transport = telegram.connection.kind;
  const std::uint16_t service = answered_request(telegram.payload);
  std::vector<faults::FaultEvent> used;
  std::optional<faults::ActiveFault> fault;
  for (const FaultKind kind : kTapKinds) {
    fault = injector_->scheduler().take_wire_fault(telegram.at, kind, transport, service, used);
    if (fault) break;
  }
  fault_injection::InjectorOutput output;
  injector_->events_from(used, output);
  // A reply leaves after the request changed the state: STATE_CHANGED goes out with it.
  injector_->note_state(telegram.at, output.events);
  for (const auto& event : output.events) publish(event);
  if (!fault) return WireVerdict::pass;
  switch (fault->spec.kind) {
    case FaultKind::drop_reply:
      return WireVerdict::drop;
    case FaultKind::delay_reply:
      delay(telegram, fault->spec.delay);
      return WireVerdict::drop;
    case FaultKind::duplicate_reply:
      device_.send_to_host(telegram.connection, telegram.payload, telegram.is_profile);
      return WireVerdict::pass;
    case FaultKind::truncate_reply:
      telegram.payload.resize(std::min<std::size_t>(telegram.payload.size(), fault->spec.bytes_kept));
      return WireVerdict::pass;
    case FaultKind::tcp_reset:
      device_.disconnect(telegram.connection);
      return WireVerdict::drop;
    default:
      return WireVerdict::pass;
  }
}

// Issue 27 D1: the replies held back per connection are bounded (kMaxDelayedTelegrams,
// kMaxDelayedBytes). A reply beyond the bound is lost, as in a device whose send buffer is full:
// counted (delayed_replies_dropped) and warned about at most every 10 s.
void FaultWiring::delay(const endpoints::WireTelegram& telegram, SimTime by) {
  const protocol::ConnectionId to = telegram.connection;
  DelayedReplies& held = delayed_[to];
  if (held.pending.size() >= kMaxDelayedTelegrams || held.bytes + telegram.payload.size() > kMaxDelayedBytes) {
    ++delayed_dropped_;
    if (auto line = delayed_warning_.admit("delay_reply: " + protocol::to_string(to) + " already holds " +
                                           std::to_string(held.pending.size()) + " delayed replies (" +
                                           std::to_string(held.bytes) + " bytes); dropping this one")) {
      logger_.log(LogLevel::warn, *line);
    }
    return;
  }
  const std::size_t size = telegram.payload.size();
  auto key = std::make_shared<endpoints::Scheduler::Key>();
  *key = scheduler_.add(telegram.at + by, [this, to, key, size, payload = telegram.payload,
                                           profile = telegram.is_profile](SimTime) {
    release(to, *key, size);
    device_.send_to_host(to, payload, profile);
  });
  held.pending.insert(*key);
  held.bytes += size;
}

void FaultWiring::release(protocol::ConnectionId connection, const endpoints::Scheduler::Key& key, std::size_t size) {
  const auto held = delayed_.find(connection);
  if (held == delayed_.end() || held->second.pending.erase(key) == 0) return;
  held->second.bytes -= size;
  if (held->second.pending.empty()) delayed_.erase(held);
}

// A closed connection's delayed replies have nobody to go to: their deadlines go with it.
void FaultWiring::forget_delayed(protocol::ConnectionId connection) {
  const auto held = delayed_.find(connection);
  if (held == delayed_.end()) return;
  for (const auto& key : held->second.pending) scheduler_.cancel(key);
  delayed_.erase(held);
}

control_socket::CommandResult FaultWiring::inject_fault(const faults::FaultSpec& spec) {
  faults::FaultId id = 0;
  take(injector_->inject(scheduler_.now(), spec, id));
  return nlohmann::json{{"id", id}};
}

control_socket::CommandResult FaultWiring::clear_fault(std::optional<std::uint64_t> id) {
  bool found = false;
  take(injector_->clear(scheduler_.now(), id, found));
  if (!found) return control_socket::CommandError{std::string(control_socket::kGenericError), "no active fault " + std::to_string(*id)};
  return nlohmann::json::object();
}

nlohmann::json FaultWiring::query_faults() { return injector_->query_faults(); }

nlohmann::json FaultWiring::query_status() {
  const control::ControlUnit& unit = device_.unit();
  const endpoints::Counters counters = device_.counters();
  const SimTime now = scheduler_.now();
  const fault_injection::Power power = injector_->power();
  const bool on = power == fault_injection::Power::on;
  // Off or booting there is no device state a host could read: state OFF or BOOTING, the head
  // stopped, no status byte (docs/faults.md, "The control socket").
  nlohmann::json status{
      {"time_s", std::chrono::duration<double>(now).count()},
      {"powered", power != fault_injection::Power::off},
      {"state", on ? std::string(control::describe(unit.state().mode)) : std::string(fault_injection::describe(power))},
      {"head_hz", on ? unit.state().head.speed_hz : 0},
      {"tilt_steps", device_.steps_seen()},
      {"faults_active", injector_->scheduler().active().size()},
      {"counters",
       {{"telegrams_received", counters.telegrams_received},
        {"framing_errors", counters.framing_errors},
        {"profiles_sent", counters.profiles_sent},
        {"skipped_profiles", counters.skipped_profiles},
        {"tcp_connections", counters.tcp_connections},
        {"delayed_replies_dropped", delayed_dropped_},
        {"event_log_write_errors", event_log_.write_errors()},
        {"fault_injections", injector_->injections()},
        {"mesh_trees_built_on_loop", mesh_trees_on_loop_}}}};
  if (on) status["status_byte"] = unit.status_byte().to_byte();
  return status;
}

void FaultWiring::quit() { stop_(); }

}  // namespace ldoem::daemon
