// Errors of the I/O edges as typed values: which operation failed, on what, and why (errno).
// Printed as one line that names the operation and the object, as can-utils does
// (design.md convention 1): `bind vcan0: No such device`.
#pragma once

#include <string>

#include "ldoem/base/expected.hpp"

namespace ldoem::io {

struct IoError {
  std::string operation;  // the syscall or step: "socket", "bind", "epoll_ctl", "can"
  std::string object;     // interface, path or address it was applied to; may be empty
  int error_number = 0;   // errno value (ENODEV, ENETDOWN, ...); callers branch on this
  std::string detail;     // replaces strerror(error_number) in message() when not empty

  // "operation object: reason" (or "operation: reason" without an object).
  std::string message() const;
};

// The error of a failed syscall, from the current errno.
IoError last_system_error(std::string operation, std::string object = {});

// Marks an operation that succeeded and has nothing to return.
struct Done {};

template <class T>
using IoResult = base::Expected<T, IoError>;
using IoStatus = IoResult<Done>;

inline base::Unexpected<IoError> io_failure(IoError error) {
  return base::Unexpected<IoError>(std::move(error));
}

}  // namespace ldoem::io
