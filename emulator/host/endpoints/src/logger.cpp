#include "ldoem/endpoints/logger.hpp"

namespace ldoem::endpoints {

std::string_view to_string(LogLevel level) {
  switch (level) {
    case LogLevel::error: return "error";
    case LogLevel::warn: return "warn";
    case LogLevel::info: return "info";
    case LogLevel::debug: return "debug";
  }
  return "?";
}

void Logger::log(LogLevel level, std::string_view text) const {
  if (!enabled(level)) {
    return;
  }
  out_ << "ldoem-emud: " << to_string(level) << ": " << text << '\n' << std::flush;
}

}  // namespace ldoem::endpoints
