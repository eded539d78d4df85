#include "ldoem/monitor/monitor.hpp"

namespace ldoem::monitor {

using endpoints::LogLevel;

Monitor::Monitor(io::EventLoop& loop, endpoints::Scheduler& scheduler, const endpoints::Logger& logger, Setup setup,
                 std::function<void()> stop)
    : loop_(loop),
      scheduler_(scheduler),
      logger_(logger),
      stop_(std::move(stop)),
      world_(setup.world),
      no_world_(std::move(setup.no_world)),
      imports_off_loop_(setup.imports_off_loop),
      several_(setup.several_scanners) {}

Monitor::~Monitor() { abandon_import(); }

base::Expected<std::unique_ptr<Monitor>, std::string> Monitor::open(io::EventLoop& loop, endpoints::Scheduler& scheduler,
                                                                    const endpoints::Logger& logger, Setup setup,
                                                                    std::function<void()> stop) {
  const std::optional<std::string> control_path = setup.control_path;
  const std::optional<std::string> event_log_path = setup.event_log_path;
  const std::string version = setup.version;
  std::unique_ptr<Monitor> monitor(new Monitor(loop, scheduler, logger, std::move(setup), std::move(stop)));
  if (event_log_path) {
    if (auto error = monitor->event_log_.open(*event_log_path)) return base::Unexpected(*error);
  }
  if (control_path) {
    Monitor* self = monitor.get();
    auto server = control_socket::ControlServer::open(
        loop, *control_path, control_socket::greeting_line(version),
        [self](std::string_view line) { return control_socket::handle_line(line, *self); });
    if (!server) return base::Unexpected("--control: " + server.error().message());
    monitor->server_ = std::move(*server);
    monitor->server_->set_warning_sink([&logger](const std::string& line) { logger.log(LogLevel::warn, line); });
  }
  return monitor;
}

ScannerTarget& Monitor::add_scanner(std::string name, fault_injection::FaultTap* faults, const DeviceReadings& readings) {
  scanners_.push_back(std::make_unique<ScannerTarget>(*this, std::move(name), faults, readings, scanners_.empty()));
  return *scanners_.back();
}

void Monitor::publish(std::string_view scanner, fault_injection::InjectorEvent event) {
  if (several_ && (event.data.is_object() || event.data.is_null())) event.data["scanner"] = std::string(scanner);
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

void Monitor::publish_daemon(fault_injection::InjectorEvent event) {
  publish(scanners_.empty() ? std::string_view() : std::string_view(scanners_.front()->name()), std::move(event));
}

control_socket::CommandResult Monitor::inject_fault(const faults::FaultSpec& spec) {
  return scanners_.front()->inject_fault(spec);
}

control_socket::CommandResult Monitor::clear_fault(std::optional<std::uint64_t> id) {
  return scanners_.front()->clear_fault(id);
}

nlohmann::json Monitor::query_faults() { return scanners_.front()->query_faults(); }

nlohmann::json Monitor::query_status() { return scanners_.front()->query_status(); }

control_socket::ControlTarget* Monitor::scanner(std::string_view name) {
  for (const auto& target : scanners_) {
    if (name == target->name()) return target.get();
  }
  return nullptr;
}

}  // namespace ldoem::monitor
