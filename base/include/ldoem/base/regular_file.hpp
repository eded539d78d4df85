// Issue 27: every file the programs read or create (scene, mesh, flash, event log, recording,
// capture) must be a regular file, or not exist where it is created. A FIFO would hang open()
// or read() (and the daemon blocks its signals early), /dev/zero never ends, a folder reads as
// nothing. open_regular_file opens with O_NONBLOCK, so that open() never waits, and refuses what
// fstat says is not a regular file, naming what it is ("is a FIFO").
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "ldoem/base/expected.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::base {

struct FileError {
  int error_number = 0;  // errno of the failed call; 0 when the file is not a regular file
  std::string text;      // "is a FIFO, not a regular file", "cannot open: Permission denied"
};

// "a FIFO", "a directory", "a character device", "a block device", "a socket", "a regular file".
std::string_view file_type_name(mode_t mode);

// open(2) with O_NONBLOCK | O_CLOEXEC | O_NOCTTY added, then fstat: anything but a regular file
// is closed again and refused. O_NONBLOCK is cleared before returning (it means nothing for a
// regular file). With O_CREAT a missing file is created; an existing FIFO, device or folder at
// the path is refused and left as it was (O_TRUNC does not act on them).
[[nodiscard]] Expected<UniqueFd, FileError> open_regular_file(const std::filesystem::path& path, int flags,
                                                              mode_t mode = 0644);

// The whole content of a regular file of at most max_bytes. The bound is applied to the bytes
// actually read, not to st_size (which a file can change after fstat, and /proc files report as
// 0). The error text says "larger than N bytes" past the bound.
[[nodiscard]] Expected<std::string, FileError> read_regular_file(const std::filesystem::path& path,
                                                                 std::uintmax_t max_bytes);

}  // namespace ldoem::base
