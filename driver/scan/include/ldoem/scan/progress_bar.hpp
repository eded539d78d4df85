// A terminal progress bar for ldoem-scan: "\r[=====>    ] 42% layer 100/240". It draws only
// when the stream is a terminal, at most once per min_interval (the caller passes the time, the
// bar never reads a clock), always draws the last step, and ends with one newline.
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
};

class ProgressBar {
 public:
  // is_terminal: whether `out` is a terminal; nothing is written when it is not.
  ProgressBar(std::ostream& out, bool is_terminal, ProgressBarOptions options = {});

  // A bar on std::cerr, drawn when stderr is a terminal (isatty).
  static ProgressBar for_stderr(ProgressBarOptions options = {});

  // done of total steps at time `now` (any monotonic time base). Draws when it is the first
  // draw, when done >= total, or when min_interval has passed since the last draw.
  void update(std::uint64_t done, std::uint64_t total, std::chrono::nanoseconds now);

  // Ends the line (once). Call after the last update; later updates draw nothing.
  void finish();

  // The text one update would draw (no "\r"), e.g. "[====>     ] 42% layer 100/240".
  [[nodiscard]] std::string render(std::uint64_t done, std::uint64_t total) const;

 private:
  std::ostream& out_;
  bool is_terminal_;
  ProgressBarOptions options_;
  std::optional<std::chrono::nanoseconds> last_draw_;
  std::size_t last_length_ = 0;
  bool finished_ = false;
};

}  // namespace ldoem::scan
