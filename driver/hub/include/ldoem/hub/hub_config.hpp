// The hub's device list and settings, from YAML (docs/hub.md):
//
//   listen: 127.0.0.1:49200        # optional; --listen overrides
//   max_age_ms: 50                 # optional; --max-age-ms overrides
//   devices:
//     - name: left                 # [A-Za-z0-9_.-], unique
//       scanner: tcp:127.0.0.1:49152
//       lpt: lpt:pty:/tmp/ldoem-lpt   # optional
//       stepper: { rate_hz: 200, max_move_ms: 120000 }  # optional: MOVEMOTOR's default rate
//                                     # and the longest move it accepts
//       request_timeout_ms: 5000      # optional (spec 6)
//       profile_timeout_ms: 5000      # optional, GET2DPROFILE's wait
//
// parse_hub_config is pure (text in, value or one-line error out).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/driver/endpoint.hpp"
#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/hub/device_vocabulary.hpp"
#include "ldoem/hub/listen_address.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::hub {

inline constexpr std::chrono::milliseconds kDefaultMaxAge{50};
inline constexpr std::chrono::milliseconds kDefaultProfileTimeout{5000};

struct HubDeviceConfig {
  std::string name;
  driver::Endpoint scanner;
  std::optional<driver::Endpoint> lpt;
  driver::StepperDefaults stepper;
  std::chrono::milliseconds request_timeout = driver::kDefaultRequestTimeout;
  std::chrono::milliseconds profile_timeout = kDefaultProfileTimeout;
  driver::ReconnectPolicy reconnect;  // how the hub reopens a lost connection to the device
  bool operator==(const HubDeviceConfig&) const = default;
};

struct HubConfig {
  std::optional<ListenAddress> listen;
  std::optional<std::chrono::milliseconds> max_age;
  std::vector<HubDeviceConfig> devices;
  bool operator==(const HubConfig&) const = default;
};

base::Expected<HubConfig, std::string> parse_hub_config(std::string_view yaml_text);

}  // namespace ldoem::hub
