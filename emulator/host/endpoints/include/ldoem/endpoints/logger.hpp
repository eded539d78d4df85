// One-line diagnostics on a stream (stderr in the daemon), filtered by --log-level.
// Telegrams are logged in the protocol's text form (protocol/text.hpp).
#pragma once

#include <concepts>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>

namespace ldoem::endpoints {

enum class LogLevel : std::uint8_t { error, warn, info, debug };

std::string_view to_string(LogLevel level);

class Logger {
 public:
  Logger(std::ostream& out, LogLevel level) : out_(out), level_(level) {}

  bool enabled(LogLevel level) const { return level <= level_; }
  // "ldoem-emud: info: tcp#1 -> GET_STATUS"
  void log(LogLevel level, std::string_view text) const;
  // The text made only when the level is printed: a telegram's text form costs more than the
  // telegram's handling, and at the default level (warn) every one would be thrown away.
  template <std::invocable MakeText>
  void log(LogLevel level, MakeText&& make_text) const {
    if (!enabled(level)) return;
    const std::string text = make_text();
    log(level, std::string_view(text));
  }

 private:
  std::ostream& out_;
  LogLevel level_;
};

}  // namespace ldoem::endpoints
