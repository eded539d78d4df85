#include "ldoem/scan/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace ldoem::scan {

std::string format_time_left(std::chrono::nanoseconds left) {
  const auto seconds = std::max<long long>(0, std::chrono::duration_cast<std::chrono::seconds>(left).count());
  char text[32];
  if (seconds < 60) {
    std::snprintf(text, sizeof text, "%llds", seconds);
  } else if (seconds < 3600) {
    std::snprintf(text, sizeof text, "%lldm%02llds", seconds / 60, seconds % 60);
  } else {
    std::snprintf(text, sizeof text, "%lldh%02lldm", seconds / 3600, seconds / 60 % 60);
  }
  return text;
}

ProgressBar::ProgressBar(std::ostream& out, bool is_terminal, ProgressBarOptions options)
    : out_(out), is_terminal_(is_terminal), options_(std::move(options)) {}

ProgressBar ProgressBar::for_stderr(ProgressBarOptions options) {
  return ProgressBar(std::cerr, ::isatty(STDERR_FILENO) == 1, std::move(options));
}

std::uint64_t ProgressBar::percent(std::uint64_t done, std::uint64_t total) const {
  const std::uint64_t clamped = std::min(done, total);
  // Nearest whole percent, but 100 % only once every step is done.
  const std::uint64_t rounded = total == 0 ? 100 : (clamped * 200 + total) / (2 * total);
  return clamped < total ? std::min<std::uint64_t>(rounded, 99) : rounded;
}

std::string ProgressBar::status(std::uint64_t done, std::uint64_t total,
                                std::optional<std::chrono::nanoseconds> left) const {
  std::string text = std::to_string(percent(done, total)) + "% " + options_.unit + " " + std::to_string(done) + "/" +
                     std::to_string(total);
  if (left && done < total) text += ", " + format_time_left(*left) + " left";
  return text;
}

std::string ProgressBar::render(std::uint64_t done, std::uint64_t total,
                                std::optional<std::chrono::nanoseconds> left) const {
  const std::uint64_t width = options_.bar_width;
  const std::uint64_t filled = total == 0 ? width : std::min(done, total) * width / total;
  std::string text = "[";
  text.append(filled, '=');
  if (filled < width) {
    text += '>';
    text.append(width - filled - 1, ' ');
  }
  return text + "] " + status(done, total, left);
}

std::optional<std::chrono::nanoseconds> ProgressBar::time_left(std::uint64_t done, std::uint64_t total,
                                                               std::chrono::nanoseconds now) const {
  if (!first_update_ || done <= first_update_->first || done >= total) return std::nullopt;
  const auto elapsed = now - first_update_->second;
  const auto steps = static_cast<long long>(done - first_update_->first);
  return elapsed / steps * static_cast<long long>(total - done);
}

void ProgressBar::update(std::uint64_t done, std::uint64_t total, std::chrono::nanoseconds now) {
  if (finished_) return;
  if (!first_update_) first_update_ = std::pair{done, now};
  const auto left = time_left(done, total, now);
  if (!is_terminal_) {
    const std::uint64_t tenth = percent(done, total) / 10;
    if (last_tenth_ && tenth <= *last_tenth_) return;
    last_tenth_ = tenth;
    out_ << options_.line_prefix << status(done, total, left) << '\n' << std::flush;
    return;
  }
  const bool complete = done >= total;
  const bool due = !last_draw_ || now - *last_draw_ >= options_.min_interval;
  if (!complete && !due) return;
  std::string text = render(done, total, left);
  const std::size_t length = text.size();
  // A shorter line must blank what is left of the previous one.
  if (length < last_length_) text.append(last_length_ - length, ' ');
  out_ << '\r' << text << std::flush;
  last_draw_ = now;
  last_length_ = length;
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (is_terminal_ && last_draw_) out_ << '\n' << std::flush;
}

}  // namespace ldoem::scan
