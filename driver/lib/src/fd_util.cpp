#include "fd_util.hpp"

#include <cerrno>
#include <chrono>
#include <limits>

namespace ldoem::driver::detail {

int poll_timeout_ms(Deadline deadline) {
  const auto remaining = deadline - Clock::now();
  if (remaining <= Clock::duration::zero()) {
    return 0;
  }
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(remaining).count();
  return ms > std::numeric_limits<int>::max() ? std::numeric_limits<int>::max() : static_cast<int>(ms);
}

Expected<WaitOutcome, DriverError> wait_for(int fd, short events, Deadline deadline,
                                            const std::string& operation, const std::string& object) {
  while (true) {
    pollfd entry{fd, events, 0};
    const int timeout_ms = poll_timeout_ms(deadline);
    const int result = ::poll(&entry, 1, timeout_ms);
    if (result > 0) {
      return WaitOutcome::ready;
    }
    if (result == 0) {
      if (Clock::now() >= deadline) {
        return WaitOutcome::deadline_passed;
      }
      continue;  // poll's millisecond rounding woke us a little early
    }
    if (errno != EINTR) {
      return fail(system_error(operation, object, errno));
    }
  }
}

}  // namespace ldoem::driver::detail
