#include "ldoem/base/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ldoem::base {
namespace {

FileError os_error(const char* step, int error_number) {
  return FileError{error_number, std::string(step) + ": " + std::strerror(error_number)};
}

FileError not_regular(mode_t mode) {
  return FileError{0, "is " + std::string(file_type_name(mode)) + ", not a regular file"};
}

}  // namespace

std::string_view file_type_name(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

Expected<UniqueFd, FileError> open_regular_file(const std::filesystem::path& path, int flags, mode_t mode) {
  UniqueFd fd(::open(path.c_str(), flags | O_NONBLOCK | O_CLOEXEC | O_NOCTTY, mode));
  if (!fd.valid()) {
    const int error_number = errno;
    // A FIFO opened for writing without a reader fails with ENXIO, a folder with EISDIR, a
    // socket with ENXIO: say what the path is rather than the errno text.
    struct stat info {};
    if ((error_number == ENXIO || error_number == EISDIR || error_number == EOPNOTSUPP) &&
        ::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
      return Unexpected(not_regular(info.st_mode));
    }
    return Unexpected(os_error("cannot open", error_number));
  }
  struct stat info {};
  if (::fstat(fd.get(), &info) != 0) return Unexpected(os_error("fstat", errno));
  if (!S_ISREG(info.st_mode)) return Unexpected(not_regular(info.st_mode));
  const int status = ::fcntl(fd.get(), F_GETFL);
  if (status < 0 || ::fcntl(fd.get(), F_SETFL, status & ~O_NONBLOCK) != 0) return Unexpected(os_error("fcntl", errno));
  return fd;
}

Expected<std::string, FileError> read_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  auto fd = open_regular_file(path, O_RDONLY);
  if (!fd) return Unexpected(std::move(fd.error()));
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(fd->get(), buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return Unexpected(os_error("cannot read", errno));
    if (got == 0) return text;
    if (text.size() + static_cast<std::size_t>(got) > max_bytes) {
      return Unexpected(FileError{EFBIG, "larger than " + std::to_string(max_bytes) + " bytes"});
    }
    text.append(buffer, static_cast<std::size_t>(got));
  }
}

}  // namespace ldoem::base
