#include "stream_io.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

#include "fd_util.hpp"

namespace ldoem::driver::detail {
namespace {

ssize_t recv_some(int fd, void* buffer, std::size_t size) { return ::recv(fd, buffer, size, 0); }
ssize_t send_some(int fd, const void* data, std::size_t size) { return ::send(fd, data, size, MSG_NOSIGNAL); }
ssize_t read_some(int fd, void* buffer, std::size_t size) { return ::read(fd, buffer, size); }
ssize_t write_some(int fd, const void* data, std::size_t size) { return ::write(fd, data, size); }

bool means_try_again(int errno_value) {
  return errno_value == EINTR || errno_value == EAGAIN || errno_value == EWOULDBLOCK;
}

// Waits for `events` on `fd`; the error names the operation and, at the deadline, `timeout_detail`.
Status wait_until(int fd, short events, Deadline deadline, const char* operation, const std::string& name,
                  const char* timeout_detail) {
  const auto waited = wait_for(fd, events, deadline, operation, name);
  if (!waited) {
    return fail(waited.error());
  }
  if (*waited == WaitOutcome::deadline_passed) {
    return fail(make_error(ErrorKind::timeout, operation, name, timeout_detail));
  }
  return ok();
}

}  // namespace

const StreamKind kTcpStream{recv_some, send_some, "peer closed the connection", false,
                            "socket not writable before the deadline"};
const StreamKind kSerialLine{read_some, write_some, "line hung up", true, "line not writable before the deadline"};
const StreamKind kIsoTpDatagrams{read_some, write_some, "", false, "telegram not sent before the deadline"};

Expected<std::size_t, DriverError> read_when_ready(int fd, std::span<std::uint8_t> buffer, Deadline deadline,
                                                   const StreamKind& kind, const std::string& name) {
  while (true) {
    if (auto ready = wait_until(fd, POLLIN, deadline, "receive", name, "no telegram before the deadline"); !ready) {
      return fail(ready.error());
    }
    const ssize_t count = kind.read_some(fd, buffer.data(), buffer.size());
    if (count > 0) {
      return static_cast<std::size_t>(count);
    }
    const bool ended = count == 0 ? kind.end_of_stream[0] != '\0' : kind.eio_is_end_of_stream && errno == EIO;
    if (ended) {
      return fail(make_error(ErrorKind::connection_closed, "receive", name, kind.end_of_stream));
    }
    if (count < 0 && !means_try_again(errno)) {
      return fail(system_error("receive", name, errno));
    }
  }
}

Status write_when_ready(int fd, ByteView bytes, Deadline deadline, const StreamKind& kind, const std::string& name) {
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t result = kind.write_some(fd, bytes.data() + written, bytes.size() - written);
    if (result > 0) {
      written += static_cast<std::size_t>(result);
      continue;
    }
    if (result < 0 && errno == EINTR) {
      continue;
    }
    if (result < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (auto room = wait_until(fd, POLLOUT, deadline, "send", name, kind.no_room); !room) {
        return room;
      }
      continue;
    }
    return fail(system_error("send", name, errno));
  }
  return ok();
}

}  // namespace ldoem::driver::detail
