#include "ldoem/test_support/raw_tty.hpp"

#include <fcntl.h>
#include <termios.h>

namespace ldoem::test_support {

int open_raw(const std::string& path, int extra_flags) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | extra_flags);
  if (fd < 0) return -1;
  termios settings{};
  ::tcgetattr(fd, &settings);
  ::cfmakeraw(&settings);
  ::tcsetattr(fd, TCSANOW, &settings);
  return fd;
}

}  // namespace ldoem::test_support
