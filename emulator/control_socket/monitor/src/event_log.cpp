#include "ldoem/monitor/event_log.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "ldoem/base/regular_file.hpp"

namespace ldoem::monitor {

EventLog::~EventLog() {
  if (fd_ >= 0) ::close(fd_);
}

std::optional<std::string> EventLog::open(const std::string& path) {
  path_ = path;
  // Issue 27 (D11): a FIFO, device or folder is refused at once (O_NONBLOCK, then fstat): a plain
  // open would wait for a FIFO's reader with the signals already blocked.
  auto opened = base::open_regular_file(path, O_WRONLY | O_CREAT | O_TRUNC);
  if (!opened) return "--event-log " + path + ": " + opened.error().text;
  fd_ = opened->release();
  return std::nullopt;
}

void EventLog::write(std::string_view line, const endpoints::Logger& logger) {
  if (fd_ < 0) return;
  record_.assign(line);
  record_ += '\n';
  std::size_t done = 0;
  int error = 0;
  while (done < record_.size()) {
    const ssize_t written = ::write(fd_, record_.data() + done, record_.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      error = written < 0 ? errno : ENOSPC;
      break;
    }
    done += static_cast<std::size_t>(written);
  }
  if (done == record_.size()) {
    size_ += done;
    return;
  }
  // Never half a line: the part written is taken back (ftruncate needs no free space).
  if (done > 0) (void)!::ftruncate(fd_, static_cast<off_t>(size_));
  (void)::lseek(fd_, static_cast<off_t>(size_), SEEK_SET);
  if (write_errors_++ == 0) {
    logger.log(endpoints::LogLevel::error, "--event-log " + path_ + ": write failed: " + std::strerror(error) +
                                               "; events from here on are lost until a write succeeds (counted as "
                                               "event_log_write_errors), the device goes on");
  }
}

}  // namespace ldoem::monitor
