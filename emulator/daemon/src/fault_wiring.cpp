#include "ldoem/daemon/fault_wiring.hpp"

#include <fcntl.h>

#include <algorithm>

#include "ldoem/base/regular_file.hpp"
#include "ldoem/protocol/isotp.hpp"

namespace ldoem::daemon {

using endpoints::LogLevel;
using endpoints::WireDirection;
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
    // Issue 27 (D11): a FIFO, device or folder is refused at once (O_NONBLOCK, then fstat): the
    // stream's own open would wait for a FIFO's reader with the signals already blocked.
    if (auto checked = base::open_regular_file(*setup.event_log_path, O_WRONLY | O_CREAT | O_TRUNC); !checked) {
      return base::Unexpected("--event-log " + *setup.event_log_path + ": " + checked.error().text);
    }
    wiring->event_log_.open(*setup.event_log_path, std::ios::out | std::ios::trunc);
    if (!wiring->event_log_) return base::Unexpected("--event-log " + *setup.event_log_path + ": cannot open");
  }
  FaultWiring* self = wiring.get();
  if (setup.control_path) {
    auto server = control_socket::ControlServer::open(
        loop, *setup.control_path, control_socket::greeting_line(setup.version),
        [self](std::string_view line) { return control_socket::handle_line(line, *self); });
    if (!server) return base::Unexpected("--control: " + server.error().message());
    wiring->server_ = std::move(*server);
  }
  wiring->attach(scene.faults, scene.seed, scene.effects.has(scene::Effect::head_dynamics));
  // Scanner k draws with the seed + k, as its noise does (docs/scenes.md).
  for (std::size_t k = 1; k < devices.size() && k < scene.scanners.size(); ++k) {
    std::unique_ptr<FaultWiring> other(new FaultWiring(*devices[k], scheduler, logger, stop));
    other->name_ = scene.scanners[k].name;
    other->first_ = self;
    other->attach({}, scene.seed + k, scene.scanners[k].effects.has(scene::Effect::head_dynamics));
    wiring->others_.push_back(std::move(other));
  }
  return wiring;
}

void FaultWiring::attach(std::vector<faults::FaultSpec> scene_faults, std::uint64_t seed, bool head_dynamics) {
  injector_ = std::make_unique<fault_injection::FaultInjector>(std::move(scene_faults), seed, head_dynamics,
                                                               device_.unit_for_faults());
  endpoint_faults_ = std::make_unique<EndpointFaults>(
      *injector_, [this](fault_injection::InjectorOutput output) { take(std::move(output)); });
  device_.set_fault_hook(endpoint_faults_.get());
  device_.set_connection_observer([this](bool opened, control::ConnectionId connection, std::string_view peer) {
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
      event_log_ << control_socket::event_line(event.name, data, event.at) << '\n' << std::flush;
    } else {
      event_log_ << line << '\n' << std::flush;
    }
  }
  if (server_) server_->broadcast(line);
}

void FaultWiring::take(fault_injection::InjectorOutput output) {
  if (!output.actions.telegrams.empty() || !output.actions.timers.empty() || output.actions.flash_image) {
    device_.perform_actions(scheduler_.now(), output.actions);
  }
  if (output.drop_all_connections) {
    const auto connections = std::move(connections_);
    connections_.clear();
    for (const control::ConnectionId connection : connections) device_.disconnect(connection);
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
  const faults::Transport transport = transport_of(telegram.connection.kind);
  const bool silenced = [&] {
    const faults::ActiveFault* silence = injector_->scheduler().find_active(FaultKind::can_silence);
    return silence && transport == faults::Transport::can;
  }();
  if (telegram.direction == WireDirection::to_host) {
    if (!injector_->powered() || silenced) return WireVerdict::drop;
    return to_host(telegram);
  }
  if (!injector_->powered()) {
    // The device is off: a TCP peer is refused at once, CAN and serial hear nothing.
    if (transport == faults::Transport::tcp) device_.disconnect(telegram.connection);
    return WireVerdict::drop;
  }
  if (silenced) return WireVerdict::drop;
  connections_.insert(telegram.connection);
  const std::uint16_t service =
      telegram.payload.size() >= 2 ? static_cast<std::uint16_t>((telegram.payload[0] << 8) | telegram.payload[1]) : 0;
  // A multi-frame ISO-TP request was seen at its first frame already (EndpointFaults).
  const bool came_in_frames = transport == faults::Transport::can && telegram.payload.size() > protocol::kIsoTpMaxSingleFrameBytes;
  take(injector_->on_request(telegram.at, service, transport,
                             came_in_frames ? faults::RequestSeen::rest_of_multi_frame : faults::RequestSeen::whole));
  if (!injector_->powered()) return WireVerdict::drop;  // a power cycle this very request started
  return WireVerdict::pass;
}

WireVerdict FaultWiring::to_host(endpoints::WireTelegram& telegram) {
  const faults::Transport transport = transport_of(telegram.connection.kind);
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
    case FaultKind::delay_reply: {
      const control::ConnectionId to = telegram.connection;
      scheduler_.add(telegram.at + fault->spec.delay,
                     [this, to, payload = telegram.payload, profile = telegram.is_profile](SimTime) {
                       device_.send_to_host(to, payload, profile);
                     });
      return WireVerdict::drop;
    }
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
  return nlohmann::json{
      {"time_s", std::chrono::duration<double>(now).count()},
      {"powered", injector_->powered()},
      {"state", std::string(control::describe(unit.state().mode))},
      {"status_byte", unit.status_byte().to_byte()},
      {"head_hz", unit.state().head.speed_hz},
      {"tilt_steps", device_.steps_seen()},
      {"faults_active", injector_->scheduler().active().size()},
      {"counters",
       {{"telegrams_received", counters.telegrams_received},
        {"framing_errors", counters.framing_errors},
        {"profiles_sent", counters.profiles_sent},
        {"skipped_profiles", counters.skipped_profiles},
        {"tcp_connections", counters.tcp_connections},
        {"fault_injections", injector_->injections()},
        {"mesh_trees_built_on_loop", mesh_trees_on_loop_}}}};
}

void FaultWiring::quit() { stop_(); }

}  // namespace ldoem::daemon
