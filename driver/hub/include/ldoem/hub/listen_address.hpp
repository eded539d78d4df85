// Where a hub listens and where a client finds it: "HOST:PORT", "[v6]:PORT" or ":PORT".
// Apart from the YAML configuration (hub_config.hpp) so that a client (HubClient, ldoem-scan
// --hub) parses an address without linking yaml-cpp.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "ldoem/base/expected.hpp"

namespace ldoem::hub {

inline constexpr std::uint16_t kDefaultHubPort = 49200;

struct ListenAddress {
  std::string host = "127.0.0.1";  // loopback by default: the hub has no authentication
  std::uint16_t port = kDefaultHubPort;
  bool operator==(const ListenAddress&) const = default;
};

// "HOST:PORT", "[v6]:PORT" or ":PORT" (loopback); the error is one line.
base::Expected<ListenAddress, std::string> parse_listen_address(std::string_view text);

}  // namespace ldoem::hub
