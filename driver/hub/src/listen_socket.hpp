// The hub's listening socket: resolve, bind and listen, non-blocking and close-on-exec.
#pragma once

#include <cstdint>

#include "ldoem/driver/error.hpp"
#include "ldoem/hub/listen_address.hpp"

namespace ldoem::hub {

struct ListeningSocket {
  int fd = -1;
  std::uint16_t port = 0;  // the bound port (the ephemeral one when 0 was asked for)
};

driver::Expected<ListeningSocket, driver::DriverError> open_listening_socket(const ListenAddress& address);

}  // namespace ldoem::hub
