#include "ldoem/hub/hub_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "ldoem/base/endpoint.hpp"
#include "ldoem/base/numbers.hpp"

namespace ldoem::hub {
namespace {

using base::Unexpected;
using ConfigResult = base::Expected<HubConfig, std::string>;

Unexpected<std::string> config_error(std::string text) { return Unexpected<std::string>(std::move(text)); }

bool is_device_name(const std::string& name) {
  if (name.empty() || name.size() > 32) {
    return false;
  }
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '.' || c == '-';
    if (!ok) {
      return false;
    }
  }
  return true;
}

base::Expected<std::chrono::milliseconds, std::string> milliseconds_of(const YAML::Node& node,
                                                                         const std::string& where) {
  const auto value = node.as<long long>();
  if (value < 0) {
    return config_error(where + " must not be negative");
  }
  return std::chrono::milliseconds(value);
}

// `reconnect: {attempts, interval_ms, backoff, max_interval_ms}`, each optional (libldoem's
// ReconnectPolicy; bounded like ldoem-scan's --reconnect-* so that a typo cannot hold a device
// in reconnects for hours).
std::optional<std::string> parse_reconnect(const YAML::Node& node, const std::string& where, driver::ReconnectPolicy& policy) {
  if (!node.IsMap()) {
    return where + " is not a map";
  }
  for (const auto& entry : node) {
    const auto key = entry.first.as<std::string>();
    if (key != "attempts" && key != "interval_ms" && key != "backoff" && key != "max_interval_ms") {
      return where + ": unknown key `" + key + "`";
    }
  }
  if (node["attempts"]) {
    const auto attempts = node["attempts"].as<long long>();
    if (attempts < 1 || attempts > 1000) {
      return where + ".attempts must be in 1..1000";
    }
    policy.attempts = static_cast<std::uint32_t>(attempts);
  }
  for (const auto& [key, field] : {std::pair{"interval_ms", &driver::ReconnectPolicy::interval},
                                   std::pair{"max_interval_ms", &driver::ReconnectPolicy::max_interval}}) {
    if (node[key]) {
      const auto value = node[key].as<long long>();
      if (value < 1 || value > 600000) {
        return where + "." + key + " must be in 1..600000";
      }
      policy.*field = std::chrono::milliseconds(value);
    }
  }
  if (node["backoff"]) {
    const double backoff = node["backoff"].as<double>();
    if (!std::isfinite(backoff) || backoff < 1.0 || backoff > 10.0) {
      return where + ".backoff must be in [1, 10]";
    }
    policy.backoff = backoff;
  }
  return std::nullopt;
}

base::Expected<HubDeviceConfig, std::string> parse_device(const YAML::Node& node, std::size_t index) {
  const std::string where = "devices[" + std::to_string(index) + "]";
  if (!node.IsMap()) {
    return config_error(where + " is not a map");
  }
  for (const auto& entry : node) {
    const auto key = entry.first.as<std::string>();
    static const std::set<std::string> kKnown{"name", "scanner", "lpt", "stepper", "request_timeout_ms",
                                              "profile_timeout_ms", "reconnect"};
    if (!kKnown.contains(key)) {
      return config_error(where + ": unknown key `" + key + "`");
    }
  }
  HubDeviceConfig device;
  if (!node["name"] || !is_device_name(node["name"].as<std::string>())) {
    return config_error(where + ".name must be 1..32 of [A-Za-z0-9_.-]");
  }
  device.name = node["name"].as<std::string>();
  if (!node["scanner"]) {
    return config_error(where + ".scanner is missing");
  }
  // The endpoint grammar of every tool (docs/endpoints.md); the hub connects.
  auto scanner = base::parse_endpoint(node["scanner"].as<std::string>(),
                                      base::EndpointUse{base::EndpointSide::connect, base::EndpointExpect::scanner});
  if (!scanner) {
    return config_error(where + ".scanner: " + base::describe(scanner.error()));
  }
  device.scanner = scanner.value();
  if (node["lpt"]) {
    auto lpt = base::parse_endpoint(node["lpt"].as<std::string>(),
                                    base::EndpointUse{base::EndpointSide::connect, base::EndpointExpect::lpt});
    if (!lpt) {
      return config_error(where + ".lpt: " + base::describe(lpt.error()));
    }
    device.lpt = lpt.value();
  }
  if (const YAML::Node stepper = node["stepper"]) {
    if (stepper["rate_hz"]) {
      const double rate = stepper["rate_hz"].as<double>();
      if (!std::isfinite(rate) || rate < kMinStepRateHz || rate > kMaxStepRateHz) {
        return config_error(where + ".stepper.rate_hz must be in [" + std::to_string(kMinStepRateHz) + ", " +
                            std::to_string(kMaxStepRateHz) + "] Hz");
      }
      device.stepper.step_rate_hz = rate;
    }
    if (stepper["max_move_ms"]) {
      auto limit = milliseconds_of(stepper["max_move_ms"], where + ".stepper.max_move_ms");
      if (!limit) {
        return config_error(limit.error());
      }
      device.stepper.max_move_duration = limit.value();
    }
  }
  if (node["request_timeout_ms"]) {
    auto timeout = milliseconds_of(node["request_timeout_ms"], where + ".request_timeout_ms");
    if (!timeout) {
      return config_error(timeout.error());
    }
    device.request_timeout = timeout.value();
  }
  if (node["profile_timeout_ms"]) {
    auto timeout = milliseconds_of(node["profile_timeout_ms"], where + ".profile_timeout_ms");
    if (!timeout) {
      return config_error(timeout.error());
    }
    device.profile_timeout = timeout.value();
  }
  if (const YAML::Node reconnect = node["reconnect"]) {
    if (auto problem = parse_reconnect(reconnect, where + ".reconnect", device.reconnect)) {
      return config_error(*problem);
    }
  }
  return device;
}

ConfigResult parse_root(const YAML::Node& root) {
  if (!root.IsMap()) {
    return config_error("the hub configuration is not a YAML map");
  }
  HubConfig config;
  if (root["listen"]) {
    auto listen = parse_listen_address(root["listen"].as<std::string>());
    if (!listen) {
      return config_error("listen: " + listen.error());
    }
    config.listen = listen.value();
  }
  if (root["max_age_ms"]) {
    auto age = milliseconds_of(root["max_age_ms"], "max_age_ms");
    if (!age) {
      return config_error(age.error());
    }
    config.max_age = age.value();
  }
  const YAML::Node devices = root["devices"];
  if (!devices || !devices.IsSequence() || devices.size() == 0) {
    return config_error("devices: a non-empty list is needed");
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    auto device = parse_device(devices[i], i);
    if (!device) {
      return config_error(device.error());
    }
    if (!names.insert(device->name).second) {
      return config_error("devices: the name `" + device->name + "` is used twice");
    }
    config.devices.push_back(std::move(device.value()));
  }
  return config;
}

}  // namespace

base::Expected<HubConfig, std::string> parse_hub_config(std::string_view yaml_text) {
  // yaml-cpp reports errors by exception; they stop here (no exceptions across our APIs).
  try {
    return parse_root(YAML::Load(std::string(yaml_text)));
  } catch (const YAML::Exception& error) {
    return config_error(std::string("YAML: ") + error.what());
  }
}

}  // namespace ldoem::hub
