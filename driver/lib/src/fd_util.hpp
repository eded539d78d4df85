// Waiting on one descriptor until a monotonic deadline, shared by the transports and LPT ports
// (ownership is base::UniqueFd).
#pragma once

#include <poll.h>
#include <unistd.h>

#include <string>

#include "ldoem/base/unique_fd.hpp"
#include "ldoem/driver/error.hpp"
#include "ldoem/driver/transport.hpp"

namespace ldoem::driver::detail {

enum class WaitOutcome { ready, deadline_passed };

// poll(2) on one descriptor until `events` or `deadline`. EINTR restarts the wait (the
// deadline is absolute, so the total time does not grow). POLLHUP/POLLERR count as ready: the
// following read or write reports what happened.
Expected<WaitOutcome, DriverError> wait_for(int fd, short events, Deadline deadline,
                                            const std::string& operation, const std::string& object);

// Milliseconds until `deadline` for poll(2), rounded up, 0 when passed.
int poll_timeout_ms(Deadline deadline);

}  // namespace ldoem::driver::detail
