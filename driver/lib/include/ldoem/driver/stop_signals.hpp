// SIGINT and SIGTERM as a readable descriptor (signalfd), so that a tool's loop sees a stop
// request like any other input, with no handler and no global flag. ldoem-hub and ldoem-scan
// set it up this one way and exit with 128 + the signal's number (design.md convention 1).
#pragma once

#include <utility>

#include "ldoem/base/unique_fd.hpp"
#include "ldoem/driver/error.hpp"

namespace ldoem::driver {

class StopSignals {
 public:
  // Restores the default disposition of both signals (a shell starts background jobs with
  // SIGINT ignored, and an ignored signal never reaches a signalfd), blocks them in the calling
  // thread and opens the descriptor. Call it before starting threads: they inherit the mask, so
  // no thread is killed by the signal the descriptor should report.
  static Expected<StopSignals, DriverError> block_and_open();

  // Readable once SIGINT or SIGTERM is pending.
  int fd() const { return fd_.get(); }

  // The pending signal's number, taken off the descriptor; 0 when none is pending. Never blocks.
  int take_pending();

 private:
  explicit StopSignals(base::UniqueFd fd) : fd_(std::move(fd)) {}
  base::UniqueFd fd_;
};

}  // namespace ldoem::driver
