// File-descriptor helpers shared by the transports and LPT ports: ownership, and waiting on
// one descriptor until a monotonic deadline.
#pragma once

#include <poll.h>
#include <unistd.h>

#include <string>
#include <utility>

#include "ldoem/driver/error.hpp"
#include "ldoem/driver/transport.hpp"

namespace ldoem::driver::detail {

class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept {
    if (this != &other) {
      reset();
      fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }

  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }
  bool valid() const { return fd_ >= 0; }
  void reset() {
    if (fd_ >= 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }

 private:
  int fd_ = -1;
};

enum class WaitOutcome { ready, deadline_passed };

// poll(2) on one descriptor until `events` or `deadline`. EINTR restarts the wait (the
// deadline is absolute, so the total time does not grow). POLLHUP/POLLERR count as ready: the
// following read or write reports what happened.
Expected<WaitOutcome, DriverError> wait_for(int fd, short events, Deadline deadline,
                                            const std::string& operation, const std::string& object);

// Milliseconds until `deadline` for poll(2), rounded up, 0 when passed.
int poll_timeout_ms(Deadline deadline);

}  // namespace ldoem::driver::detail
