#include "ldoem/daemon/endpoint_registry.hpp"

#include "ldoem/endpoints/can_endpoint.hpp"
#include "ldoem/endpoints/lpt_gpio_endpoint.hpp"
#include "ldoem/endpoints/lpt_pty_endpoint.hpp"
#include "ldoem/endpoints/serial_endpoint.hpp"
#include "ldoem/endpoints/tcp_endpoint.hpp"

namespace ldoem::daemon {
namespace {

using Made = std::unique_ptr<endpoints::HostEndpoint>;

Made make_can(const Options& options, const DeviceFacts& device) {
  if (!options.can_interface) return nullptr;
  return std::make_unique<endpoints::CanHostEndpoint>(endpoints::CanEndpointSetup{
      *options.can_interface, options.can_id_pairs, device.can_config,
      device.scene.effects.has(scene::Effect::bus_timing)});
}

Made make_tcp(const Options& options, const DeviceFacts&) {
  if (!options.tcp) return nullptr;
  return std::make_unique<endpoints::TcpHostEndpoint>(options.tcp->address, options.tcp->port, options.host_limits);
}

Made make_serial(const Options& options, const DeviceFacts&) {
  if (!options.serial_pty) return nullptr;
  return std::make_unique<endpoints::SerialHostEndpoint>(*options.serial_pty, options.host_limits.inter_byte_timeout);
}

Made make_lpt_pty(const Options& options, const DeviceFacts&) {
  if (!options.lpt || options.lpt->backend != LptBackend::pty) return nullptr;
  return std::make_unique<endpoints::LptPtyEndpoint>(options.lpt->target);
}

Made make_lpt_gpio(const Options& options, const DeviceFacts&) {
  if (!options.lpt || options.lpt->backend != LptBackend::gpio) return nullptr;
  return std::make_unique<endpoints::LptGpioEndpoint>(options.lpt->target);
}

}  // namespace

const std::vector<EndpointEntry>& endpoint_registry() {
  static const std::vector<EndpointEntry> registry{
      {"can", make_can},
      {"tcp", make_tcp},
      {"serial", make_serial},
      {"lpt", make_lpt_pty},
      {"lpt-gpio", make_lpt_gpio},
  };
  return registry;
}

}  // namespace ldoem::daemon
