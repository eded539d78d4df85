// ldoem-hub: reads the device list, opens one back-end handler per device, serves clients
// until SIGINT/SIGTERM (docs/hub.md).
#include <systemd/sd-daemon.h>

#include <fstream>
#include <iostream>
#include <sstream>

#include "ldoem/base/command_line.hpp"
#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/driver/stop_signals.hpp"
#include "ldoem/hub/hub_options.hpp"
#include "ldoem/hub/hub_server.hpp"

namespace {

using namespace ldoem::hub;
using ldoem::driver::ScannerDevice;
using ldoem::driver::ScannerDeviceOptions;

std::vector<DeviceSlot> make_devices(const HubConfig& config) {
  std::vector<DeviceSlot> slots;
  for (const HubDeviceConfig& device : config.devices) {
    ScannerDeviceOptions options;
    options.scanner.request_timeout = device.request_timeout;
    options.scanner.reconnect = device.reconnect;
    options.stepper = device.stepper;
    slots.push_back(DeviceSlot{device.name,
                               ScannerDevice::from_endpoints(device.name, device.scanner, device.lpt, options),
                               device.profile_timeout});
  }
  return slots;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  auto command_line = parse_hub_command_line(args);
  if (!command_line) {
    std::cerr << ldoem::base::usage_error_line("ldoem-hub", command_line.error());
    return kExitUsage;
  }
  if (command_line->version) {
    std::cout << ldoem::base::version_line("ldoem-hub");
    return kExitOk;
  }
  if (command_line->help_all) {
    std::cout << hub_usage("ldoem-hub");
    return 0;
  }
  if (command_line->help) {
    std::cout << hub_brief_usage("ldoem-hub");
    return kExitOk;
  }
  if (command_line->completion_script) {
    std::cout << *command_line->completion_script;
    return kExitOk;
  }
  std::ifstream file(command_line->config_path);
  if (!file) {
    std::cerr << "ldoem-hub: open " << command_line->config_path << ": cannot read the file\n";
    return kExitUsage;
  }
  std::stringstream text;
  text << file.rdbuf();
  auto config = parse_hub_config(text.str());
  if (!config) {
    std::cerr << "ldoem-hub: " << command_line->config_path << ": " << config.error() << "\n";
    return kExitUsage;
  }

  HubSettings settings;
  settings.listen = command_line->listen.value_or(config->listen.value_or(ListenAddress{}));
  settings.max_age = command_line->max_age.value_or(config->max_age.value_or(kDefaultMaxAge));
  settings.max_clients = command_line->max_clients;
  settings.queue_capacity = command_line->queue_capacity;
  settings.max_in_flight = command_line->max_in_flight;
  settings.idle_timeout = command_line->idle_timeout;

  // Signals arrive as a readable descriptor in the hub's loop; set up before the BEMH threads start.
  auto stop_signals = ldoem::driver::StopSignals::block_and_open();
  if (!stop_signals) {
    std::cerr << "ldoem-hub: " << ldoem::driver::describe(stop_signals.error()) << "\n";
    return kExitFailure;
  }

  // Under systemd (Type=notify, WatchdogSec=): the loop itself pings, so a stuck loop is
  // restarted. Outside systemd sd_watchdog_enabled() is 0 and sd_notify does nothing.
  if (std::uint64_t watchdog_us = 0; sd_watchdog_enabled(0, &watchdog_us) > 0) {
    settings.heartbeat = [] { sd_notify(0, "WATCHDOG=1"); };
    settings.heartbeat_interval = std::chrono::milliseconds(watchdog_us / 2000);
  }

  Hub hub(settings, make_devices(config.value()));
  if (auto listening = hub.listen(); !listening) {
    std::cerr << "ldoem-hub: " << ldoem::driver::describe(listening.error()) << "\n";
    return kExitFailure;
  }
  std::cerr << "ldoem-hub: listening on " << settings.listen.host << ":" << hub.port() << " with";
  for (const auto& [name, handler] : hub.devices()) {
    std::cerr << " " << name << "=" << handler;
  }
  std::cerr << "\n";
  sd_notifyf(0, "READY=1\nSTATUS=listening on %s:%u", settings.listen.host.c_str(), static_cast<unsigned>(hub.port()));
  if (auto served = hub.run(stop_signals->fd()); !served) {
    std::cerr << "ldoem-hub: " << ldoem::driver::describe(served.error()) << "\n";
    return kExitFailure;
  }
  sd_notify(0, "STOPPING=1");
  const int signal_number = stop_signals->take_pending();
  return signal_number != 0 ? kExitSignalBase + signal_number : kExitOk;
}
