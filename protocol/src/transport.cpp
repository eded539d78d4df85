#include "ldoem/protocol/transport.hpp"

#include <array>

namespace ldoem::protocol {
namespace {

constexpr std::array<std::string_view, kTransportCount> kTransportNames{"tcp", "serial", "can", "lpt"};

}  // namespace

std::string_view transport_name(Transport transport) {
  return kTransportNames.at(static_cast<std::size_t>(transport));
}

std::optional<Transport> transport_from_name(std::string_view name) {
  for (std::size_t i = 0; i < kTransportNames.size(); ++i) {
    if (kTransportNames[i] == name) return static_cast<Transport>(i);
  }
  return std::nullopt;
}

std::string to_string(ConnectionId connection) {
  return std::string(transport_name(connection.kind)) + "#" + std::to_string(connection.index);
}

}  // namespace ldoem::protocol
