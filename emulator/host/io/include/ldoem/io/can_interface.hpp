// Checks on a CAN network interface before the daemon binds to it, through libsocketcan and
// SIOCGIF* ioctls. Errors read like `can: interface vcan0 is down`.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "ldoem/io/io_error.hpp"

namespace ldoem::io {

// The controller's error state as the kernel reports it (linux/can/netlink.h).
enum class CanControllerState {
  error_active,
  error_warning,
  error_passive,
  bus_off,
  stopped,
  sleeping,
};

struct CanInterfaceStatus {
  int index = 0;  // if_nametoindex
  // Empty for interfaces without a controller (vcan, vxcan): they have no error state.
  std::optional<CanControllerState> controller_state;
};

// Succeeds when `interface_name` exists, is a CAN interface (ARPHRD_CAN) and is up, and for a
// real controller, not bus-off or stopped. Errors (operation "can"):
//   ENODEV   "interface vcan0 does not exist"
//   ENETDOWN "interface vcan0 is down"
//   EINVAL   "interface lo is not a CAN interface"
//   ENETDOWN "interface can0 is bus-off" / "... is stopped"
IoResult<CanInterfaceStatus> check_can_interface(std::string_view interface_name);

// Sets the nominal bit rate of a REAL controller (D1: 1 Mbit/s nominal) with libsocketcan's
// can_set_bitrate. Needs root (CAP_NET_ADMIN), a controller with bit timing, and the interface
// down; vcan has no bit rate and refuses (EOPNOTSUPP), so tests never call this.
IoStatus set_can_bitrate(std::string_view interface_name, std::uint32_t bitrate_bps);

}  // namespace ldoem::io
