// Endpoint strings: the one place where a user's `can:vcan0` or `lpt:pty:/tmp/ldoem-lpt`
// becomes a typed value (design.md convention 2). The grammar is base/'s (base/endpoint.hpp,
// docs/endpoints.md), shared by every tool; the driver always CONNECTS. Opening happens in
// open_transport (transport.hpp) and open_lpt_port (lpt_port.hpp).
#pragma once

#include <string>
#include <string_view>

#include "ldoem/base/endpoint.hpp"
#include "ldoem/protocol/transport.hpp"

namespace ldoem::driver {

using base::kDefaultCanRequestId;
using base::kDefaultCanResponseId;
using base::kDefaultSerialBaud;

using base::CanEndpoint;
using base::Endpoint;
using base::EndpointError;
using base::EndpointErrorKind;
using base::LptBackend;
using base::LptEndpoint;
using base::SerialEndpoint;
using base::TcpEndpoint;

using base::describe;

// The host side of the grammar: any kind (an option that takes one kind uses base's directly).
inline base::Expected<Endpoint, EndpointError> parse_endpoint(std::string_view text) {
  return base::parse_endpoint(text, base::EndpointUse{base::EndpointSide::connect, base::EndpointExpect::any});
}

// The canonical text of an endpoint (parse_endpoint(format_endpoint(e)) == e); used as the
// `object` of every DriverError about it.
inline std::string format_endpoint(const Endpoint& endpoint) { return base::to_string(endpoint); }

// The transport a connection to this endpoint uses.
inline protocol::Transport transport_of(const Endpoint& endpoint) {
  if (std::holds_alternative<CanEndpoint>(endpoint)) return protocol::Transport::can;
  if (std::holds_alternative<SerialEndpoint>(endpoint)) return protocol::Transport::serial;
  if (std::holds_alternative<LptEndpoint>(endpoint)) return protocol::Transport::lpt;
  return protocol::Transport::tcp;
}

}  // namespace ldoem::driver
