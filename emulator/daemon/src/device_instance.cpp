#include "ldoem/daemon/device_instance.hpp"

#include "ldoem/plant/scene_device_defaults.hpp"
#include "ldoem/protocol/text.hpp"

namespace ldoem::daemon {

using control::ConnectionId;
using endpoints::LogLevel;
using base::SimTime;

DeviceInstance::DeviceInstance(const scene::Scene& scene, plant::SceneWorld& world,
                               std::unique_ptr<control::FlashStore> flash, const control::DeviceConfig& flash_config,
                               endpoints::Scheduler& scheduler, const endpoints::Logger& logger,
                               std::optional<std::uint32_t> own_housing)
    : scheduler_(scheduler), logger_(logger), flash_(std::move(flash)) {
  plant_.emplace(scene, world, own_housing);
  control::ControlUnit::Setup setup;
  setup.flash = flash_config;
  setup.identification = plant::identification_from(scene.scanner.identification);
  setup.power_up_time = SimTime::zero();
  setup.flash_store = this;
  auto unit = std::make_unique<control::ControlUnit>(std::move(setup), plant_->head_model(), plant_->measurement());
  unit_ = unit.get();
  model_ = std::move(unit);
}

DeviceInstance::DeviceInstance(std::unique_ptr<control::DeviceModel> model, endpoints::Scheduler& scheduler,
                               const endpoints::Logger& logger)
    : scheduler_(scheduler), logger_(logger), model_(std::move(model)) {}

DeviceInstance::~DeviceInstance() = default;

void DeviceInstance::add_endpoint(std::unique_ptr<HostEndpoint> endpoint) { endpoints_.push_back(std::move(endpoint)); }

std::optional<endpoints::OpenFailure> DeviceInstance::open_endpoints(io::EventLoop& loop, std::ostream& out,
                                                                     std::uint64_t& activity) {
  context_.emplace(endpoints::EndpointContext{loop, scheduler_, *this, *this, logger_, out, counters_, activity});
  for (const auto& endpoint : endpoints_) {
    if (const auto kind = endpoint->transport()) {
      if (route_.contains(*kind)) {
        return endpoints::OpenFailure{true, std::string(endpoint->name()) + ": a second endpoint for " +
                                                protocol::to_string(ConnectionId{*kind, 0}) + " connections"};
      }
      route_[*kind] = endpoint.get();
    }
    if (auto failure = endpoint->open(*context_)) return failure;
  }
  return std::nullopt;
}

bool DeviceInstance::has_host_transport() const {
  for (const auto& endpoint : endpoints_) {
    if (endpoint->transport()) return true;
  }
  return false;
}

HostEndpoint* DeviceInstance::endpoint(std::string_view name) const {
  for (const auto& endpoint : endpoints_) {
    if (endpoint->name() == name) return endpoint.get();
  }
  return nullptr;
}

bool DeviceInstance::busy(ConnectionId connection) const {
  const auto route = route_.find(connection.kind);
  return route != route_.end() && route->second->busy(connection);
}

bool DeviceInstance::waiting_for_host() const {
  for (const auto& endpoint : endpoints_) {
    if (endpoint->waiting_for_host()) return true;
  }
  return false;
}

void DeviceInstance::accept_input(std::function<void()> input) {
  if (performing_ > 0) {
    deferred_input_.push_back(std::move(input));
    return;
  }
  input();
}

// ------------------------------------------------------------------------------------- input

void DeviceInstance::on_telegram(ConnectionId from, protocol::Bytes payload) {
  accept_input([this, from, payload = std::move(payload)]() mutable {
    if (tap_ != nullptr) {
      endpoints::WireTelegram telegram{protocol::WireDirection::host_to_device, from, scheduler_.now(), std::move(payload)};
      if (tap_->on_telegram(telegram) == endpoints::WireVerdict::drop) return;
      payload = std::move(telegram.payload);
    }
    deliver_from_host(from, std::move(payload));
  });
}

void DeviceInstance::deliver_from_host(ConnectionId from, protocol::Bytes payload) {
  // D8: register writes a host made before this telegram count first (host_endpoint.hpp).
  for (const auto& endpoint : endpoints_) endpoint->take_pending_input();
  ++counters_.telegrams_received;
  logger_.log(LogLevel::info, [&] { return protocol::to_string(from) + " -> " + protocol::format_telegram(payload); });
  const SimTime at = scheduler_.now();
  perform(at, model_->handle_request(at, from, payload, *this));
}

void DeviceInstance::on_framing_error(ConnectionId from, const protocol::FramingError& error) {
  accept_input([this, from, error] {
    ++counters_.framing_errors;
    logger_.log(LogLevel::info, [&] {
      return protocol::to_string(from) + " -> framing error: " + std::string(protocol::describe(error.detail));
    });
    const SimTime at = scheduler_.now();
    perform(at, model_->on_framing_error(at, from, error));
  });
}

void DeviceInstance::on_connection_opened(ConnectionId connection, std::string_view peer) {
  if (connection_observer_) connection_observer_(true, connection, peer);
}

void DeviceInstance::on_connection_closed(ConnectionId connection) {
  if (connection_observer_) connection_observer_(false, connection, {});
  // An endpoint reports the close of a connection disconnect() dropped from within that call.
  const bool reset = resetting_ == connection;
  accept_input([this, connection, reset] {
    const SimTime at = scheduler_.now();
    if (tap_ != nullptr) tap_->on_connection_closed(connection, at, reset);
    perform(at, model_->on_connection_closed(at, connection));
  });
}

void DeviceInstance::disconnect(ConnectionId connection) {
  const auto route = route_.find(connection.kind);
  if (route == route_.end()) return;
  resetting_ = connection;
  route->second->disconnect(connection);
  resetting_.reset();
}

void DeviceInstance::on_register_write(SimTime at, std::uint8_t register_value) {
  if (plant_) plant_->drive_board().on_register_write(at, register_value);
  else ++lpt_writes_;
}

void DeviceInstance::on_line_change(SimTime at, std::uint8_t bit, bool level) {
  if (plant_) plant_->drive_board().on_line_change(at, bit, level);
  else ++lpt_writes_;
}

std::uint64_t DeviceInstance::steps_seen() const { return plant_ ? plant_->drive_board().steps_seen() : lpt_writes_; }

// ------------------------------------------------------------------------------------ output

void DeviceInstance::perform(SimTime at, const control::Actions& actions) {
  ++performing_;
  for (const control::OutgoingTelegram& telegram : actions.telegrams) {
    const bool is_profile = telegram.kind == control::TelegramKind::profile;
    if (tap_ == nullptr) {
      send_to_host(telegram.to, telegram.payload, is_profile);
      continue;
    }
    endpoints::WireTelegram tapped{protocol::WireDirection::device_to_host, telegram.to, at, telegram.payload, is_profile};
    if (tap_->on_telegram(tapped) == endpoints::WireVerdict::pass) {
      send_to_host(telegram.to, tapped.payload, is_profile);
    }
  }
  for (const control::TimerId cancelled : actions.cancelled_timers) {
    if (const auto queued = timer_keys_.find(cancelled.value); queued != timer_keys_.end()) {
      scheduler_.cancel(queued->second);
      timer_keys_.erase(queued);
    }
  }
  for (const control::TimerRequest& timer : actions.timers) {
    timer_keys_[timer.id.value] = scheduler_.add(timer.at, [this, id = timer.id](SimTime now) {
      timer_keys_.erase(id.value);
      perform(now, model_->on_timer(now, id, *this));
    });
  }
  if (actions.head_target_hz) {
    if (plant_) plant_->follow_head_target(at, *actions.head_target_hz);  // D9 head_dynamics
  }
  if (actions.can_config) {
    for (const auto& endpoint : endpoints_) endpoint->apply_can_config(*actions.can_config);
  }
  if (--performing_ == 0) {
    while (!deferred_input_.empty()) {
      auto input = std::move(deferred_input_.front());
      deferred_input_.pop_front();
      input();
    }
  }
}

void DeviceInstance::send_to_host(ConnectionId to, protocol::ByteView payload, bool is_profile) {
  logger_.log(is_profile ? LogLevel::debug : LogLevel::info,
              [&] { return protocol::to_string(to) + " <- " + protocol::format_telegram(payload); });
  const auto route = route_.find(to.kind);
  if (route != route_.end()) route->second->send(to, payload);
}

control::FlashStore::Saved DeviceInstance::save(protocol::ByteView image) {
  Saved saved = flash_->save(image);
  if (!saved) logger_.log(LogLevel::error, saved.error());
  return saved;
}

bool DeviceInstance::close() {
  for (const auto& endpoint : endpoints_) endpoint->close();
  model_->report_at_exit();
  // Every store is saved (a memory store keeps the image it already had, and cannot fail).
  if (unit_ == nullptr || !flash_) return true;
  return save(control::serialise_flash_image(unit_->state().flash)).has_value();
}

Counters DeviceInstance::counters() const {
  Counters counters = counters_;
  counters.skipped_profiles = model_->diagnostics().skipped_profiles;
  counters.profiles_sent = model_->diagnostics().profiles_sent;
  counters.lpt_steps = steps_seen();
  for (const auto& endpoint : endpoints_) endpoint->add_counters(counters);
  return counters;
}

}  // namespace ldoem::daemon
