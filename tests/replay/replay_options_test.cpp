// ldoem-replay's command line: the daemon's endpoint syntax, the capture, speed and transport.
#include <gtest/gtest.h>

#include "ldoem/replay/replay_options.hpp"

namespace ldoem::replay {
namespace {

base::Expected<ReplayOptions, ReplayUsageError> parse(std::vector<std::string_view> arguments) {
  return parse_replay_options(arguments);
}

TEST(ReplayOptions, EndpointsSpeedAndTransport_AreParsed) {
  const auto options = parse({"scan.pcapng", "--tcp", "tcp:127.0.0.1:0", "--can", "can:vcan0:6C2:6C3",
                              "--lpt", "lpt:pty:/tmp/l", "--speed", "2.5", "--transport", "can", "--timeout", "9"});
  ASSERT_TRUE(options.has_value()) << options.error().message;
  EXPECT_EQ(options->capture, std::filesystem::path("scan.pcapng"));
  ASSERT_TRUE(options->endpoints.tcp.has_value());
  EXPECT_EQ(options->endpoints.tcp->port, 0);
  EXPECT_EQ(options->endpoints.can_interface, std::optional<std::string>("vcan0"));
  ASSERT_EQ(options->endpoints.can_id_pairs.size(), 1u);
  EXPECT_EQ(options->endpoints.can_id_pairs[0].request_id, 0x6C2);
  EXPECT_DOUBLE_EQ(options->speed, 2.5);
  EXPECT_EQ(options->transport, protocol::Transport::can);
  EXPECT_EQ(options->endpoints.timeout_s, std::optional<double>(9.0));
}

TEST(ReplayOptions, DefaultsServeNoCan) {
  const auto options = parse({"scan.pcapng", "--tcp", "tcp:127.0.0.1"});
  ASSERT_TRUE(options.has_value());
  EXPECT_FALSE(options->endpoints.can_interface.has_value());
  EXPECT_EQ(options->endpoints.tcp->port, 49152);
}

TEST(ReplayOptions, AreTheDaemonsReplayOptions_SpeedBeingTheTimeScale) {
  const auto options = parse({"scan.pcapng", "--tcp", "tcp:127.0.0.1:0", "--speed", "50", "--transport", "serial",
                              "--port", "4000", "--timeout", "9"});
  ASSERT_TRUE(options.has_value()) << options.error().message;
  const daemon::Options served = daemon_options(*options);
  EXPECT_EQ(served.replay_path, std::filesystem::path("scan.pcapng"));
  EXPECT_EQ(served.replay_transport, protocol::Transport::serial);
  EXPECT_EQ(served.replay_port, std::uint16_t{4000});
  EXPECT_DOUBLE_EQ(served.time_scale, 50.0);
  EXPECT_EQ(served.timeout_s, 9.0);
  EXPECT_EQ(served.flash_mode, daemon::FlashMode::memory);
  EXPECT_FALSE(served.can_interface.has_value());
  EXPECT_TRUE(served.scene_path.empty());
}

TEST(ReplayOptions, MistakesAreUsageErrorsNamingTheOption) {
  EXPECT_NE(parse({"--tcp", "tcp:127.0.0.1"}).error().message.find("CAPTURE"), std::string::npos);
  EXPECT_NE(parse({"scan.pcapng"}).error().message.find("endpoint"), std::string::npos);
  EXPECT_NE(parse({"scan.pcapng", "--tcp", "tcp:h:1", "--speed", "0"}).error().message.find("--speed"), std::string::npos);
  // Issue 11: out of range, the conversion to int64 nanoseconds would overflow (UB).
  EXPECT_NE(parse({"scan.pcapng", "--tcp", "tcp:h:1", "--speed", "1e-300"}).error().message.find("--speed"), std::string::npos);
  EXPECT_NE(parse({"scan.pcapng", "--tcp", "tcp:h:1", "--timeout", "1e300"}).error().message.find("--timeout"),
            std::string::npos);
  EXPECT_NE(parse({"scan.pcapng", "--serial", "/dev/x"}).error().message.find("--serial"), std::string::npos);
  EXPECT_NE(parse({"scan.pcapng", "--tcp", "tcp:h:1", "--can-ids", "6C0:6C1"}).error().message.find("--can-ids"),
            std::string::npos);
  EXPECT_NE(parse({"a", "b", "--tcp", "tcp:h:1"}).error().message.find("more than one"), std::string::npos);
  // Issue 24: the spellings from before docs/endpoints.md name the new ones.
  EXPECT_EQ(parse({"scan.pcapng", "--tcp", "127.0.0.1:0"}).error().message,
            "--tcp 127.0.0.1:0 is the old spelling; write --tcp tcp:127.0.0.1:0 (docs/endpoints.md)");
  EXPECT_EQ(parse({"scan.pcapng", "--tcp", "tcp:h:1", "--lpt", "pty:/x"}).error().message,
            "--lpt pty:/x is the old spelling; write --lpt lpt:pty:/x (docs/endpoints.md)");
  EXPECT_EQ(parse({"scan.pcapng", "--tcp", "tcp:h:1", "--can-ids", "6C0:6C1"}).error().message,
            "--can-ids 6C0:6C1 is the old spelling; write --can can:IF:6C0:6C1 (docs/endpoints.md)");
  EXPECT_TRUE(parse({"--help"})->help);
}

}  // namespace
}  // namespace ldoem::replay
