#include "ldoem/io/io_error.hpp"

#include <gtest/gtest.h>

#include <cerrno>

namespace ldoem::io {
namespace {

TEST(IoError, Message_NamesOperationObjectAndReason) {
  const IoError error{"bind", "vcan0", ENODEV, {}};
  EXPECT_EQ(error.message(), "bind vcan0: No such device");
}

TEST(IoError, MessageWithoutObject_HasNoDoubleSpace) {
  const IoError error{"epoll_create1", {}, EMFILE, {}};
  EXPECT_EQ(error.message(), "epoll_create1: Too many open files");
}

TEST(IoError, Detail_ReplacesTheErrnoText) {
  const IoError error{"can", {}, ENETDOWN, "interface vcan0 is down"};
  EXPECT_EQ(error.message(), "can: interface vcan0 is down");
}

TEST(IoError, LastSystemError_CapturesErrno) {
  errno = EACCES;
  const IoError error = last_system_error("open", "/dev/gpiochip0");
  EXPECT_EQ(error.error_number, EACCES);
  EXPECT_EQ(error.message(), "open /dev/gpiochip0: Permission denied");
}

}  // namespace
}  // namespace ldoem::io
