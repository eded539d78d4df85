// `ldoem-emud --event-log FILE` (D11): one JSON line per event. Issue 27 D10: each record goes
// out with one write(2) and is whole or absent: a write that fails (a full disk, /dev/full)
// cuts the file back to the end of the previous record. The first failure is reported once on
// the log (error level), every lost record is counted; the device goes on and exits as usual,
// since the event log is a diagnostic beside the device and not part of what it serves.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/endpoints/logger.hpp"

namespace ldoem::monitor {

class EventLog {
 public:
  EventLog() = default;
  ~EventLog();
  EventLog(const EventLog&) = delete;
  EventLog& operator=(const EventLog&) = delete;

  // Creates or truncates `path`; the error text when it cannot.
  [[nodiscard]] std::optional<std::string> open(const std::string& path);
  bool is_open() const { return fd_ >= 0; }
  // One record; `line` has no newline. A failure is reported through `logger` the first time.
  void write(std::string_view line, const endpoints::Logger& logger);
  std::uint64_t write_errors() const { return write_errors_; }

 private:
  int fd_ = -1;
  std::string path_;
  std::uint64_t size_ = 0;          // bytes of whole records in the file
  std::uint64_t write_errors_ = 0;  // records lost
  std::string record_;              // reused buffer: the line and its newline
};

}  // namespace ldoem::monitor
