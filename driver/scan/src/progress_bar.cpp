#include "ldoem/scan/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <iostream>

namespace ldoem::scan {

ProgressBar::ProgressBar(std::ostream& out, bool is_terminal, ProgressBarOptions options)
    : out_(out), is_terminal_(is_terminal), options_(std::move(options)) {}

ProgressBar ProgressBar::for_stderr(ProgressBarOptions options) {
  return ProgressBar(std::cerr, ::isatty(STDERR_FILENO) == 1, std::move(options));
}

std::string ProgressBar::render(std::uint64_t done, std::uint64_t total) const {
  const std::uint64_t clamped = std::min(done, total);
  const std::uint64_t width = options_.bar_width;
  const std::uint64_t filled = total == 0 ? width : clamped * width / total;
  // Nearest whole percent, but 100 % only once every step is done.
  const std::uint64_t rounded = total == 0 ? 100 : (clamped * 200 + total) / (2 * total);
  const std::uint64_t percent = clamped < total ? std::min<std::uint64_t>(rounded, 99) : rounded;
  std::string text = "[";
  text.append(filled, '=');
  if (filled < width) {
    text += '>';
    text.append(width - filled - 1, ' ');
  }
  text += "] " + std::to_string(percent) + "% " + options_.unit + " " + std::to_string(done) + "/" +
          std::to_string(total);
  return text;
}

void ProgressBar::update(std::uint64_t done, std::uint64_t total, std::chrono::nanoseconds now) {
  if (!is_terminal_ || finished_) return;
  const bool complete = done >= total;
  const bool due = !last_draw_ || now - *last_draw_ >= options_.min_interval;
  if (!complete && !due) return;
  std::string text = render(done, total);
  const std::size_t length = text.size();
  // A shorter line must blank what is left of the previous one.
  if (length < last_length_) text.append(last_length_ - length, ' ');
  out_ << '\r' << text << std::flush;
  last_draw_ = now;
  last_length_ = length;
}

void ProgressBar::finish() {
  if (!is_terminal_ || finished_) return;
  finished_ = true;
  if (last_draw_) out_ << '\n' << std::flush;
}

}  // namespace ldoem::scan
