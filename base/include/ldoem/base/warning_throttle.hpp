// A warning a host can trigger as often as it likes (a connect flood, descriptors running out)
// is said at most once per period, with the number held back since it was last said: the log
// stays readable and a flood cannot fill the disk or block on a full stderr (issue 11). One
// class for the daemon's endpoints and fault wiring and the hub's accept loop.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

namespace ldoem::base {

class WarningThrottle {
 public:
  using Clock = std::chrono::steady_clock;
  explicit WarningThrottle(Clock::duration period) : period_(period) {}

  // The line to log now ("LINE (N more since the last report)" after held-back ones), or
  // nothing while the period since the last one said has not passed.
  std::optional<std::string> admit(std::string line, Clock::time_point now = Clock::now()) {
    if (said_once_ && now - last_said_ < period_) {
      ++held_back_;
      return std::nullopt;
    }
    if (held_back_ > 0) line += " (" + std::to_string(held_back_) + " more since the last report)";
    said_once_ = true;
    last_said_ = now;
    held_back_ = 0;
    return line;
  }

 private:
  Clock::duration period_;
  bool said_once_ = false;
  Clock::time_point last_said_{};
  std::uint64_t held_back_ = 0;
};

}  // namespace ldoem::base
