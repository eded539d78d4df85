// ldoem-scan's progress on stderr. On a terminal: one bar redrawn in place,
// "\r[=====>    ] 42% layer 100/240, 1m05s left", at most once per min_interval, always the
// last step, ended by one newline. Elsewhere (a CI log, a file): one whole line each time the
// scan passes another tenth, "42% layer 100/240, 1m05s left", so a log shows progress without
// a carriage-return smear. The time left is the mean time per step so far times the steps left,
// shown from the second step on. The caller passes the time; the bar never reads a clock.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

namespace ldoem::scan {

struct ProgressBarOptions {
  std::string unit = "layer";  // word before "done/total"
  std::uint32_t bar_width = 30;  // characters between the brackets
  std::chrono::nanoseconds min_interval = std::chrono::milliseconds(100);
  std::string line_prefix;  // not a terminal: put before each line ("ldoem-scan: ")
};

// "45s", "1m05s", "2h03m": a duration as a person reads it.
[[nodiscard]] std::string format_time_left(std::chrono::nanoseconds left);

class ProgressBar {
 public:
  // is_terminal: whether `out` is a terminal (a bar) or not (a line per tenth).
  ProgressBar(std::ostream& out, bool is_terminal, ProgressBarOptions options = {});

  // On std::cerr, a bar when stderr is a terminal (isatty), else lines.
  static ProgressBar for_stderr(ProgressBarOptions options = {});

  // done of total steps at time `now` (any monotonic time base).
  void update(std::uint64_t done, std::uint64_t total, std::chrono::nanoseconds now);

  // Ends the bar's line (once). Call after the last update; later updates draw nothing.
  void finish();

  // The bar one update would draw (no "\r"), e.g. "[====>     ] 42% layer 100/240, 45s left".
  [[nodiscard]] std::string render(std::uint64_t done, std::uint64_t total,
                                   std::optional<std::chrono::nanoseconds> left = std::nullopt) const;

 private:
  [[nodiscard]] std::uint64_t percent(std::uint64_t done, std::uint64_t total) const;
  [[nodiscard]] std::string status(std::uint64_t done, std::uint64_t total,
                                   std::optional<std::chrono::nanoseconds> left) const;
  [[nodiscard]] std::optional<std::chrono::nanoseconds> time_left(std::uint64_t done, std::uint64_t total,
                                                                  std::chrono::nanoseconds now) const;

  std::ostream& out_;
  bool is_terminal_;
  ProgressBarOptions options_;
  std::optional<std::chrono::nanoseconds> last_draw_;
  std::optional<std::pair<std::uint64_t, std::chrono::nanoseconds>> first_update_;  // (done, time)
  std::optional<std::uint64_t> last_tenth_;  // not a terminal: the last tenth reported
  std::size_t last_length_ = 0;
  bool finished_ = false;
};

}  // namespace ldoem::scan
