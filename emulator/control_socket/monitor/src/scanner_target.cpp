#include "ldoem/monitor/scanner_target.hpp"

#include <chrono>

#include "ldoem/monitor/monitor.hpp"

namespace ldoem::monitor {

using fault_injection::Power;

namespace {

// A recorded device's answer to a fault command: the FaultInjector acts on a control unit.
control_socket::CommandResult not_for_recorded(std::string_view command) {
  return control_socket::CommandError{std::string(control_socket::kGenericError),
                                      std::string(command) + ": " + std::string(kNotForRecorded)};
}

}  // namespace

control_socket::CommandResult ScannerTarget::inject_fault(const faults::FaultSpec& spec) {
  if (faults_ == nullptr) {
    return not_for_recorded(spec.kind == faults::FaultKind::power_cycle ? "power-cycle" : "inject-fault");
  }
  return nlohmann::json{{"id", faults_->inject(spec)}};
}

control_socket::CommandResult ScannerTarget::clear_fault(std::optional<std::uint64_t> id) {
  if (faults_ == nullptr) return not_for_recorded("clear-fault");
  if (!faults_->clear(id)) {
    return control_socket::CommandError{std::string(control_socket::kGenericError), "no active fault " + std::to_string(*id)};
  }
  return nlohmann::json::object();
}

nlohmann::json ScannerTarget::query_status() {
  const control::ControlUnit* unit = readings_.unit();
  const endpoints::Counters counters = readings_.counters();
  const Power power = faults_ != nullptr ? faults_->power() : Power::on;
  // A recorded device (no control unit) has no state of its own to show: RECORDED, no status byte.
  const bool on = power == Power::on && unit != nullptr;
  // Off or booting there is no device state a host could read: state OFF or BOOTING, the head
  // stopped, no status byte (docs/faults.md, "The control socket").
  const std::string state = unit == nullptr ? std::string("RECORDED")
                            : on            ? std::string(control::describe(unit->state().mode))
                                            : std::string(fault_injection::describe(power));
  nlohmann::json status{
      {"time_s", std::chrono::duration<double>(monitor_.now()).count()},
      {"powered", power != Power::off},
      {"state", state},
      {"head_hz", on ? unit->state().head.speed_hz : 0},
      {"tilt_steps", readings_.tilt_steps()},
      {"faults_active", faults_ != nullptr ? faults_->faults_active() : 0},
      {"counters",
       {{"telegrams_received", counters.telegrams_received},
        {"framing_errors", counters.framing_errors},
        {"profiles_sent", counters.profiles_sent},
        {"skipped_profiles", counters.skipped_profiles},
        {"tcp_connections", counters.tcp_connections},
        {"delayed_replies_dropped", faults_ != nullptr ? faults_->delayed_replies_dropped() : 0},
        {"event_log_write_errors", first_ ? monitor_.event_log_write_errors() : 0},
        {"fault_injections", faults_ != nullptr ? faults_->injections() : 0},
        {"mesh_trees_built_on_loop", first_ ? monitor_.mesh_trees_built_on_loop() : 0}}}};
  if (on) status["status_byte"] = unit->status_byte().to_byte();
  return status;
}

void ScannerTarget::quit() { monitor_.quit(); }

void ScannerTarget::on_connection(bool opened, protocol::ConnectionId connection, std::string_view peer) {
  const std::string label = protocol::to_string(connection);  // "tcp#3"
  nlohmann::json data{{"transport", label.substr(0, label.find('#'))}, {"connection", connection.index}};
  if (opened) {
    peers_[connection] = std::string(peer);
    data["peer"] = std::string(peer);
  } else if (const auto known = peers_.find(connection); known != peers_.end()) {
    data["peer"] = known->second;
    peers_.erase(known);
  }
  monitor_.publish(name_, {opened ? "CONNECTION_OPENED" : "CONNECTION_CLOSED", data, monitor_.now()});
}

}  // namespace ldoem::monitor
