#include "ldoem/io/gpio_lines.hpp"

#include <fcntl.h>
#include <gpiod.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <string_view>

namespace ldoem::io {
namespace {

// "gpiochip" followed by one or more decimal digits: a kernel chip name, not a label.
bool is_chip_name(std::string_view chip) {
  constexpr std::string_view prefix = "gpiochip";
  if (!chip.starts_with(prefix) || chip.size() == prefix.size()) {
    return false;
  }
  const std::string_view digits = chip.substr(prefix.size());
  return std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

gpiod_chip* open_chip(const std::string& chip) {
  if (!chip.empty() && chip.front() == '/') {
    return ::gpiod_chip_open(chip.c_str());
  }
  if (is_chip_name(chip)) {
    return ::gpiod_chip_open_by_name(chip.c_str());
  }
  return ::gpiod_chip_open_by_label(chip.c_str());
}

std::chrono::nanoseconds to_duration(const timespec& time) {
  return std::chrono::seconds(time.tv_sec) + std::chrono::nanoseconds(time.tv_nsec);
}

}  // namespace

void GpioLineReader::ChipCloser::operator()(gpiod_chip* chip) const { ::gpiod_chip_close(chip); }

GpioLineReader::GpioLineReader(std::unique_ptr<gpiod_chip, ChipCloser> chip, std::string chip_name,
                               std::vector<std::string> line_names, std::vector<gpiod_line*> lines)
    : chip_(std::move(chip)),
      chip_name_(std::move(chip_name)),
      line_names_(std::move(line_names)),
      lines_(std::move(lines)) {}

GpioLineReader::GpioLineReader(GpioLineReader&&) noexcept = default;
GpioLineReader& GpioLineReader::operator=(GpioLineReader&&) noexcept = default;
GpioLineReader::~GpioLineReader() = default;

IoResult<GpioLineReader> GpioLineReader::open(std::string_view chip,
                                              const std::vector<std::string>& line_names,
                                              std::string_view consumer) {
  const std::string chip_text(chip);
  errno = 0;
  std::unique_ptr<gpiod_chip, ChipCloser> handle(open_chip(chip_text));
  if (!handle) {
    // by_label reports a missing label as ENOENT; keep that, and never report errno 0.
    return io_failure(IoError{"gpiod_chip_open", chip_text, errno != 0 ? errno : ENOENT, {}});
  }
  const std::string chip_name = ::gpiod_chip_name(handle.get());
  const std::string consumer_text(consumer);
  std::vector<gpiod_line*> lines;
  for (const std::string& name : line_names) {
    errno = 0;
    gpiod_line* line = ::gpiod_chip_find_line(handle.get(), name.c_str());
    if (line == nullptr) {
      return io_failure(IoError{"gpiod_chip_find_line", chip_name + " line " + name,
                                errno != 0 ? errno : ENOENT, "no line of that name"});
    }
    if (::gpiod_line_request_both_edges_events(line, consumer_text.c_str()) != 0) {
      return io_failure(last_system_error("gpiod_line_request_both_edges_events",
                                          chip_name + " line " + name));
    }
    const int fd = ::gpiod_line_event_get_fd(line);
    const int flags = fd < 0 ? -1 : ::fcntl(fd, F_GETFL);
    if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0) {
      return io_failure(last_system_error("fcntl O_NONBLOCK", chip_name + " line " + name));
    }
    lines.push_back(line);
  }
  return GpioLineReader(std::move(handle), chip_name, line_names, std::move(lines));
}

std::vector<int> GpioLineReader::event_fds() const {
  std::vector<int> fds;
  fds.reserve(lines_.size());
  for (gpiod_line* line : lines_) {
    fds.push_back(::gpiod_line_event_get_fd(line));
  }
  return fds;
}

IoResult<std::vector<GpioEdgeEvent>> GpioLineReader::read_events() {
  std::vector<GpioEdgeEvent> events;
  for (std::size_t index = 0; index < lines_.size(); ++index) {
    for (;;) {
      std::array<gpiod_line_event, 16> batch{};
      const int got = ::gpiod_line_event_read_multiple(lines_[index], batch.data(),
                                                       static_cast<unsigned>(batch.size()));
      if (got < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) {
          break;
        }
        if (errno == EINTR) {
          continue;
        }
        return io_failure(last_system_error("gpiod_line_event_read",
                                            chip_name_ + " line " + line_names_[index]));
      }
      for (int i = 0; i < got; ++i) {
        const gpiod_line_event& raw = batch[static_cast<std::size_t>(i)];
        events.push_back(GpioEdgeEvent{
            index, raw.event_type == GPIOD_LINE_EVENT_RISING_EDGE ? Edge::rising : Edge::falling,
            to_duration(raw.ts)});
      }
      if (got < static_cast<int>(batch.size())) {
        break;
      }
    }
  }
  std::stable_sort(events.begin(), events.end(),
                   [](const GpioEdgeEvent& a, const GpioEdgeEvent& b) {
                     return a.timestamp < b.timestamp;
                   });
  return events;
}

IoResult<std::vector<int>> GpioLineReader::levels() {
  std::vector<int> values;
  values.reserve(lines_.size());
  for (std::size_t index = 0; index < lines_.size(); ++index) {
    const int value = ::gpiod_line_get_value(lines_[index]);
    if (value < 0) {
      return io_failure(
          last_system_error("gpiod_line_get_value", chip_name_ + " line " + line_names_[index]));
    }
    values.push_back(value);
  }
  return values;
}

}  // namespace ldoem::io
