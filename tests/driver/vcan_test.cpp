// CAN transports on a real vcan0 (ctest label `vcan`, run inside User-Mode Linux). Every test
// here FAILS when vcan0 is missing: a harness that forgot to create it must not pass.
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <future>
#include <thread>

#include "ldoem/driver/can_transport.hpp"
#include "ldoem/driver/scanner.hpp"

namespace ldoem::driver {
namespace {

using namespace std::chrono_literals;

constexpr const char* kInterface = "vcan0";

#define REQUIRE_VCAN0()                                                                      \
  do {                                                                                       \
    if (::if_nametoindex(kInterface) == 0) {                                                 \
      FAIL() << "vcan0 is missing: run the vcan tests through scripts/uml/run.sh, which "    \
                "creates it";                                                                \
    }                                                                                        \
  } while (false)

CanEndpoint host_side() { return CanEndpoint{kInterface, 0x6C0, 0x6C1, false}; }
// The peer answers on the response id and listens on the request id.
CanEndpoint device_side() { return CanEndpoint{kInterface, 0x6C1, 0x6C0, false}; }

std::unique_ptr<CanIsoTpTransport> open_user_space(const CanEndpoint& endpoint, IsoTpOptions options = {}) {
  auto transport = CanIsoTpTransport::open(endpoint, options);
  if (!transport) {
    ADD_FAILURE() << describe(transport.error());
    return nullptr;
  }
  return std::move(*transport);
}

Bytes pattern(std::size_t size, std::uint8_t seed) {
  Bytes bytes(size);
  for (std::size_t i = 0; i < size; ++i) {
    bytes[i] = static_cast<std::uint8_t>(seed + i * 7);
  }
  return bytes;
}

// A raw socket that sees the frames of one identifier.
class RawSniffer {
 public:
  explicit RawSniffer(std::uint32_t id) {
    fd_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    can_filter filter{id, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
    ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter);
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(::if_nametoindex(kInterface));
    ::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address);
  }
  ~RawSniffer() { ::close(fd_); }
  std::optional<can_frame> next(int timeout_ms = 2000) {
    pollfd entry{fd_, POLLIN, 0};
    if (::poll(&entry, 1, timeout_ms) <= 0) {
      return std::nullopt;
    }
    can_frame frame{};
    if (::read(fd_, &frame, sizeof frame) != static_cast<ssize_t>(sizeof frame)) {
      return std::nullopt;
    }
    return frame;
  }

 private:
  int fd_ = -1;
};

TEST(VcanIsoTp, ShortTelegram_IsOneUnpaddedSingleFrameOnTheRequestId) {
  REQUIRE_VCAN0();
  RawSniffer sniffer(0x6C0);
  auto host = open_user_space(host_side());
  ASSERT_TRUE(host);
  ASSERT_TRUE(host->send(Bytes{0x01, 0x02}, Clock::now() + 1s));
  auto frame = sniffer.next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->can_id, 0x6C0u);
  ASSERT_EQ(frame->len, 3);  // D1: unpadded
  EXPECT_EQ(frame->data[0], 0x02);
  EXPECT_EQ(frame->data[1], 0x01);
  EXPECT_EQ(frame->data[2], 0x02);
}

TEST(VcanIsoTp, LongTelegramsBothWays_ArriveWhole) {
  REQUIRE_VCAN0();
  auto host = open_user_space(host_side());
  auto device = open_user_space(device_side());
  ASSERT_TRUE(host && device);
  const Bytes request = pattern(5000, 3);  // above 4095: the 32-bit first-frame escape (D1)
  const Bytes reply = pattern(5816, 9);
  auto peer = std::async(std::launch::async, [&] {
    auto got = device->receive(Clock::now() + 10s);
    if (!got) {
      return got;
    }
    auto sent = device->send(reply, Clock::now() + 10s);
    if (!sent) {
      return Expected<Bytes, DriverError>(Unexpected(sent.error()));
    }
    return got;
  });
  ASSERT_TRUE(host->send(request, Clock::now() + 10s));
  auto answer = host->receive(Clock::now() + 10s);
  auto seen = peer.get();
  ASSERT_TRUE(seen) << describe(seen.error()) << "; device dropped " << device->counters().dropped_frames;
  EXPECT_EQ(*seen, request);
  ASSERT_TRUE(answer) << describe(answer.error()) << "; host dropped " << host->counters().dropped_frames;
  EXPECT_EQ(*answer, reply);
}

TEST(VcanIsoTp, DeviceFlowControlWithBlockSizeAndStMin_IsHonoured) {
  REQUIRE_VCAN0();
  RawSniffer sniffer(0x6C1);
  auto host = open_user_space(host_side());
  IsoTpOptions slow;
  slow.block_size = 2;
  slow.st_min = 1ms;
  auto device = open_user_space(device_side(), slow);
  ASSERT_TRUE(host && device);
  const Bytes request = pattern(100, 1);  // FF + 14 CF: 7 flow controls at BS 2
  auto peer = std::async(std::launch::async, [&] { return device->receive(Clock::now() + 10s); });
  ASSERT_TRUE(host->send(request, Clock::now() + 10s));
  auto seen = peer.get();
  ASSERT_TRUE(seen) << describe(seen.error());
  EXPECT_EQ(*seen, request);
  // The device's flow-control frames carry its BS and STmin.
  auto flow_control = sniffer.next();
  ASSERT_TRUE(flow_control);
  EXPECT_EQ(flow_control->data[0], 0x30);
  EXPECT_EQ(flow_control->data[1], 2);
  EXPECT_EQ(flow_control->data[2], 1);
}

TEST(VcanScanner, GetStatusOverIsoTp_Connects) {
  REQUIRE_VCAN0();
  auto device = open_user_space(device_side());
  ASSERT_TRUE(device);
  auto peer = std::async(std::launch::async, [&] {
    auto got = device->receive(Clock::now() + 5s);
    if (got && *got == Bytes{0x01, 0x02}) {
      (void)device->send(Bytes{0x81, 0x02, 0x00, 0x00, 0x00, 0x01}, Clock::now() + 5s);
    }
    return got;
  });
  auto transport = open_transport(host_side());
  ASSERT_TRUE(transport) << describe(transport.error());
  Scanner scanner(std::move(*transport));
  auto status = scanner.connect();
  ASSERT_TRUE(status) << describe(status.error());
  EXPECT_EQ(status->status.status.sensor, protocol::SensorMode::idle);
  EXPECT_TRUE(peer.get());
}

TEST(VcanIsoTp, NoFlowControlFromThePeer_IsRetryableTimeout) {
  REQUIRE_VCAN0();
  IsoTpOptions quick;
  quick.timeout = 100ms;
  auto host = open_user_space(CanEndpoint{kInterface, 0x6D0, 0x6D1, false}, quick);
  ASSERT_TRUE(host);
  auto sent = host->send(pattern(20, 0), Clock::now() + 5s);  // nobody answers the FF
  ASSERT_FALSE(sent);
  EXPECT_EQ(sent.error().kind, ErrorKind::timeout);
}

TEST(VcanKernelIsoTp, OpenEitherInteroperatesOrNamesTheUserSpaceEndpoint) {
  REQUIRE_VCAN0();
  auto kernel = KernelIsoTpTransport::open(CanEndpoint{kInterface, 0x6C0, 0x6C1, true});
  if (!kernel) {
    EXPECT_EQ(kernel.error().kind, ErrorKind::unsupported) << describe(kernel.error());
    EXPECT_NE(describe(kernel.error()).find("use can:vcan0"), std::string::npos);
    return;
  }
  // The kernel's ISO-TP and ours must interoperate (D1).
  auto device = open_user_space(device_side());
  ASSERT_TRUE(device);
  const Bytes request = pattern(300, 5);
  auto peer = std::async(std::launch::async, [&] {
    auto got = device->receive(Clock::now() + 5s);
    if (got) {
      (void)device->send(*got, Clock::now() + 5s);
    }
    return got;
  });
  ASSERT_TRUE((*kernel)->send(request, Clock::now() + 5s));
  auto echo = (*kernel)->receive(Clock::now() + 5s);
  ASSERT_TRUE(echo) << describe(echo.error());
  EXPECT_EQ(*echo, request);
  EXPECT_TRUE(peer.get());
}

// Runs everywhere (no vcan needed): the message a host without can-isotp gets.
TEST(KernelIsoTpUnavailable, MessageNamesTheUserSpaceEndpoint) {
  const DriverError error = kernel_isotp_unavailable(CanEndpoint{"vcan0", 0x6C0, 0x6C1, true}, EPROTONOSUPPORT);
  EXPECT_EQ(error.kind, ErrorKind::unsupported);
  EXPECT_FALSE(is_retryable(error));
  EXPECT_EQ(describe(error),
            "socket CAN_ISOTP can:isotp:vcan0: unsupported: no CAN_ISOTP in this kernel; use can:vcan0 "
            "(user-space ISO-TP): Protocol not supported");
}

TEST(CanIsoTpTransport, MissingInterface_IsAnErrorNamingTheEndpoint) {
  auto transport = CanIsoTpTransport::open(CanEndpoint{"nocan9", 0x6C0, 0x6C1, false});
  ASSERT_FALSE(transport);
  EXPECT_EQ(transport.error().object, "can:nocan9");
  // A kernel without CAN says so and what to do (issue 24), not only strerror.
  if (transport.error().system_errno == EAFNOSUPPORT) {
    EXPECT_NE(describe(transport.error()).find("modprobe vcan"), std::string::npos) << describe(transport.error());
    EXPECT_NE(describe(transport.error()).find("docs/uml-harness.md"), std::string::npos);
  }
}

}  // namespace
}  // namespace ldoem::driver
