#include "ldoem/daemon/realtime.hpp"

#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ldoem::daemon {

RealtimeResult request_realtime() {
  RealtimeResult result;
  std::string refused;
  sched_param priority{};
  priority.sched_priority = kRealtimePriority;
  if (::sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &priority) == 0) {
    result.scheduled = true;
  } else {
    refused += std::string("SCHED_FIFO refused (") + std::strerror(errno) +
               "; needs CAP_SYS_NICE or RLIMIT_RTPRIO >= " + std::to_string(kRealtimePriority) + ")";
  }
  rlimit memlock{};
  const bool unlimited = ::getrlimit(RLIMIT_MEMLOCK, &memlock) == 0 && memlock.rlim_cur == RLIM_INFINITY;
  if (!unlimited && ::geteuid() != 0) {
    // With a finite limit MCL_FUTURE would turn a later allocation beyond it into "out of memory".
    refused += std::string(refused.empty() ? "" : ", ") + "memory not locked (RLIMIT_MEMLOCK " +
               std::to_string(memlock.rlim_cur / 1024) + " KiB, needs unlimited or CAP_IPC_LOCK)";
  } else if (::mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    result.locked = true;
  } else {
    refused += std::string(refused.empty() ? "" : ", ") + "mlockall refused (" + std::strerror(errno) + ")";
  }
  if (refused.empty()) {
    result.message = "realtime: SCHED_FIFO priority " + std::to_string(kRealtimePriority) + ", memory locked";
  } else {
    result.message = "realtime: " + refused + "; running " +
                     (result.scheduled ? "at SCHED_FIFO priority " + std::to_string(kRealtimePriority)
                                       : std::string("at normal priority")) +
                     (result.locked ? ", memory locked" : "") +
                     " (docs/latency.md: the systemd unit's realtime lines grant both)";
  }
  return result;
}

}  // namespace ldoem::daemon
