// Which endpoints a daemon opens, from its options: one entry per transport. Adding a transport
// is one file in emulator/host/endpoints and one line in endpoint_registry.cpp.
#pragma once

#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "ldoem/daemon/options.hpp"
#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::daemon {

// What an endpoint may need to know about the device it serves.
struct DeviceFacts {
  protocol::CanConfig can_config;  // RAM at power-up (D1)
  const scene::Scene& scene;
};

struct EndpointEntry {
  std::string_view name;
  // Null when the options do not ask for this endpoint.
  std::function<std::unique_ptr<endpoints::HostEndpoint>(const Options&, const DeviceFacts&)> make;
};

// In the order the endpoints open (and print their lines).
const std::vector<EndpointEntry>& endpoint_registry();

}  // namespace ldoem::daemon
