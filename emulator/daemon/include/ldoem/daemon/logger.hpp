// One-line diagnostics on a stream (stderr in the daemon), filtered by --log-level.
// Telegrams are logged in the protocol's text form (protocol/text.hpp).
#pragma once

#include <ostream>
#include <string_view>

#include "ldoem/daemon/options.hpp"

namespace ldoem::daemon {

class Logger {
 public:
  Logger(std::ostream& out, LogLevel level) : out_(out), level_(level) {}

  bool enabled(LogLevel level) const { return level <= level_; }
  // "ldoem-emud: info: tcp#1 -> GET_STATUS"
  void log(LogLevel level, std::string_view text) const;

 private:
  std::ostream& out_;
  LogLevel level_;
};

}  // namespace ldoem::daemon
