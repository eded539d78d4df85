// The serial endpoint on a pty (issue 11, spec 6): a package the host left incomplete is dropped
// after the inter-byte timeout and answered like any broken frame (D2), and the next package is
// read whole.
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <string>

#include "endpoint_harness.hpp"
#include "ldoem/endpoints/serial_endpoint.hpp"
#include "ldoem/protocol/serial_framing.hpp"

namespace ldoem::endpoints::test {
namespace {

using namespace std::chrono_literals;

struct PtyHost {
  int fd;
  explicit PtyHost(const std::string& path) : fd(::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC)) {
    termios settings{};
    ::tcgetattr(fd, &settings);
    ::cfmakeraw(&settings);
    ::tcsetattr(fd, TCSANOW, &settings);
  }
  ~PtyHost() { ::close(fd); }
  void write(const std::string& text) { ASSERT_EQ(::write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size())); }
};

TEST(SerialEndpointLimits, PackageLeftIncomplete_IsDroppedAfterTheInterByteTimeout) {
  EndpointHarness harness;
  char folder_template[] = "/tmp/ldoem-serial-test-XXXXXX";
  ASSERT_NE(::mkdtemp(folder_template), nullptr);
  const std::string link = std::string(folder_template) + "/serial";
  SerialHostEndpoint endpoint(link, 100ms);
  ASSERT_FALSE(endpoint.open(harness.context).has_value());
  {
    PtyHost host(link);
    ASSERT_GE(host.fd, 0);
    host.write("\x02" "0010000300");  // the start of spec 7.4's GET_STATUS, then nothing
    ASSERT_TRUE(harness.run_until([&] { return !harness.framing_errors.empty(); }, 2s));
    EXPECT_EQ(harness.framing_errors[0].second.detail, protocol::DecodeError::timeout);
    host.write("\x02" "00100003000001026d36" "\x03");  // spec 7.4 GET_STATUS
    ASSERT_TRUE(harness.run_until([&] { return !harness.telegrams.empty(); }, 2s));
    EXPECT_EQ(harness.telegrams[0].second, (protocol::Bytes{0x01, 0x02}));  // GET_STATUS
    EXPECT_EQ(harness.framing_errors.size(), 1u);
  }
  endpoint.close();
  ::rmdir(folder_template);
}

}  // namespace
}  // namespace ldoem::endpoints::test
