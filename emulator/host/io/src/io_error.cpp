#include "ldoem/io/io_error.hpp"

#include <cerrno>
#include <cstring>

namespace ldoem::io {

std::string IoError::message() const {
  std::string text = operation;
  if (!object.empty()) {
    text += ' ';
    text += object;
  }
  text += ": ";
  text += detail.empty() ? std::string(std::strerror(error_number)) : detail;
  return text;
}

IoError last_system_error(std::string operation, std::string object) {
  const int saved_errno = errno;
  return IoError{std::move(operation), std::move(object), saved_errno, {}};
}

}  // namespace ldoem::io
