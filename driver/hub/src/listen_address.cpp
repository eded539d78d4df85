#include "ldoem/hub/listen_address.hpp"

#include <optional>

#include "ldoem/base/numbers.hpp"

namespace ldoem::hub {

base::Expected<ListenAddress, std::string> parse_listen_address(std::string_view text) {
  using Error = base::Unexpected<std::string>;
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos) {
    return Error("`" + std::string(text) + "` is not HOST:PORT");
  }
  std::string_view host = text.substr(0, colon);
  const std::string_view port_text = text.substr(colon + 1);
  const std::optional<std::uint16_t> port = base::parse_integer<std::uint16_t>(port_text);
  if (!port) {
    return Error("`" + std::string(port_text) + "` is not a port number");
  }
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  ListenAddress address;
  if (!host.empty()) {
    address.host = std::string(host);
  }
  address.port = *port;
  return address;
}

}  // namespace ldoem::hub
