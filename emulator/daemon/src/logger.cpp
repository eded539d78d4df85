#include "ldoem/daemon/logger.hpp"

namespace ldoem::daemon {

void Logger::log(LogLevel level, std::string_view text) const {
  if (!enabled(level)) {
    return;
  }
  out_ << "ldoem-emud: " << to_string(level) << ": " << text << '\n' << std::flush;
}

}  // namespace ldoem::daemon
