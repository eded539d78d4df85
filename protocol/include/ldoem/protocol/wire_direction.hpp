// Which way a telegram or frame travels between a host and the device: the one definition used
// by the captures (pcapng packet direction), the daemon's wire tap and the recordings.
#pragma once

#include <cstdint>

namespace ldoem::protocol {

enum class WireDirection : std::uint8_t { host_to_device = 0, device_to_host = 1 };

}  // namespace ldoem::protocol
