#include "ldoem/io/can_interface.hpp"

// glibc's <net/if.h> must come before the kernel headers libsocketcan pulls in (<linux/if.h>),
// or both define struct ifreq.
#include <net/if.h>
// (keep this order)
#include <libsocketcan.h>
#include <linux/can.h>
#include <linux/can/netlink.h>
#include <linux/if_arp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "ldoem/base/endpoint.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {
namespace {

IoError can_error(int error_number, const std::string& name, const std::string& what) {
  return IoError{"can", {}, error_number, "interface " + name + " " + what};
}

IoResult<ifreq> query_interface(int fd, const std::string& name, unsigned long request,
                                const char* request_name) {
  ifreq request_data{};
  std::strncpy(request_data.ifr_name, name.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd, request, &request_data) != 0) {
    return io_failure(last_system_error(request_name, name));
  }
  return request_data;
}

std::optional<CanControllerState> controller_state_from(int state) {
  switch (state) {
    case CAN_STATE_ERROR_ACTIVE: return CanControllerState::error_active;
    case CAN_STATE_ERROR_WARNING: return CanControllerState::error_warning;
    case CAN_STATE_ERROR_PASSIVE: return CanControllerState::error_passive;
    case CAN_STATE_BUS_OFF: return CanControllerState::bus_off;
    case CAN_STATE_STOPPED: return CanControllerState::stopped;
    case CAN_STATE_SLEEPING: return CanControllerState::sleeping;
    default: return std::nullopt;
  }
}

}  // namespace

IoResult<CanInterfaceStatus> check_can_interface(std::string_view interface_name) {
  const std::string name(interface_name);
  if (name.empty() || name.size() >= IFNAMSIZ) {
    return io_failure(can_error(EINVAL, name, "is not a valid interface name"));
  }
  CanInterfaceStatus status;
  status.index = static_cast<int>(::if_nametoindex(name.c_str()));
  if (status.index == 0 && !base::UniqueFd(::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW)).valid() &&
      errno == EAFNOSUPPORT) {
    // No interface because no CAN at all: "does not exist" would send the user looking for a typo.
    return io_failure(IoError{"can", {}, EAFNOSUPPORT, "interface " + name + ": " + std::strerror(EAFNOSUPPORT) +
                                                           "; " + base::can_unsupported_hint()});
  }
  if (status.index == 0) {
    return io_failure(can_error(ENODEV, name, "does not exist"));
  }
  // Any socket can carry the interface ioctls; AF_UNIX exists even where AF_CAN does not.
  base::UniqueFd probe(::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (!probe.valid()) {
    return io_failure(last_system_error("socket AF_UNIX", name));
  }
  auto hardware = query_interface(probe.get(), name, SIOCGIFHWADDR, "ioctl SIOCGIFHWADDR");
  if (!hardware) {
    return io_failure(hardware.error());
  }
  if (hardware->ifr_hwaddr.sa_family != ARPHRD_CAN) {
    return io_failure(can_error(EINVAL, name, "is not a CAN interface"));
  }
  auto flags = query_interface(probe.get(), name, SIOCGIFFLAGS, "ioctl SIOCGIFFLAGS");
  if (!flags) {
    return io_failure(flags.error());
  }
  if ((flags->ifr_flags & IFF_UP) == 0) {
    return io_failure(can_error(ENETDOWN, name, "is down"));
  }
  // vcan and vxcan have no controller, so libsocketcan finds no state there: not an error.
  int raw_state = 0;
  if (::can_get_state(name.c_str(), &raw_state) == 0) {
    status.controller_state = controller_state_from(raw_state);
  }
  if (status.controller_state == CanControllerState::bus_off) {
    return io_failure(can_error(ENETDOWN, name, "is bus-off"));
  }
  if (status.controller_state == CanControllerState::stopped) {
    return io_failure(can_error(ENETDOWN, name, "is stopped"));
  }
  return status;
}

IoStatus set_can_bitrate(std::string_view interface_name, std::uint32_t bitrate_bps) {
  const std::string name(interface_name);
  errno = 0;
  if (::can_set_bitrate(name.c_str(), bitrate_bps) != 0) {
    const int error_number = errno != 0 ? errno : EOPNOTSUPP;
    return io_failure(IoError{"can_set_bitrate", name, error_number,
                              std::string(std::strerror(error_number)) +
                                  " (needs root, a real CAN controller and the interface down)"});
  }
  return Done{};
}

}  // namespace ldoem::io
