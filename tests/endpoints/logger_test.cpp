// The logger makes a line's text only when its level is printed (issue 22 item 9): the daemon
// logs every telegram at info or debug, and at the default level the text form of each one would
// be made and thrown away.
#include "ldoem/endpoints/logger.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace ldoem::endpoints {
namespace {

TEST(Logger, TextOfALevelNotPrintedIsNeverMade) {
  std::ostringstream out;
  const Logger logger(out, LogLevel::warn);
  int made = 0;
  logger.log(LogLevel::info, [&] {
    ++made;
    return std::string("tcp#1 -> GET_STATUS");
  });
  logger.log(LogLevel::debug, [&] {
    ++made;
    return std::string("tcp#1 <- GET_PROFILE");
  });
  EXPECT_EQ(made, 0);
  EXPECT_EQ(out.str(), "");
}

TEST(Logger, TextOfAPrintedLevelIsMadeOnceAndWritten) {
  std::ostringstream out;
  const Logger logger(out, LogLevel::info);
  int made = 0;
  logger.log(LogLevel::info, [&] {
    ++made;
    return std::string("tcp#1 -> GET_STATUS");
  });
  logger.log(LogLevel::warn, "plain text");
  EXPECT_EQ(made, 1);
  EXPECT_EQ(out.str(), "ldoem-emud: info: tcp#1 -> GET_STATUS\nldoem-emud: warn: plain text\n");
}

}  // namespace
}  // namespace ldoem::endpoints
