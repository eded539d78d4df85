#include "ldoem/base/unique_fd.hpp"

#include <unistd.h>

namespace ldoem::base {

void UniqueFd::reset(int fd) {
  if (fd_ >= 0 && fd_ != fd) {
    // Linux releases the descriptor even when close() reports EINTR or EIO; retrying could
    // close a descriptor another thread just got, so the result is deliberately not retried.
    (void)::close(fd_);
  }
  fd_ = fd;
}

}  // namespace ldoem::base
