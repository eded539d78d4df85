// ldoem-emud --replay CAPTURE (docs/replay.md): which options go with it, which are refused and
// why, and what it sets for the recorded device.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ldoem/daemon/options.hpp"

namespace ldoem::daemon {
namespace {

base::Expected<Command, UsageError> parse_replay(std::vector<std::string_view> arguments) {
  return parse_command_line(arguments);
}

TEST(ReplayOption, NeedsNoScene_NoFlashFile_CanOnlyWhenAsked) {
  const auto command = parse_replay({"--replay", "scan.pcapng", "--tcp", "tcp:127.0.0.1:0", "--record", "r.pcapng",
                                     "--replay-transport", "tcp", "--replay-port", "4000", "--time-scale", "50"});
  ASSERT_TRUE(command.has_value()) << command.error().message;
  const Options& options = command->options;
  EXPECT_EQ(options.replay_path, std::filesystem::path("scan.pcapng"));
  EXPECT_EQ(options.replay_transport, protocol::Transport::tcp);
  EXPECT_EQ(options.replay_port, std::uint16_t{4000});
  EXPECT_EQ(options.flash_mode, FlashMode::memory);
  EXPECT_TRUE(options.flash_path.empty());
  EXPECT_FALSE(options.can_interface.has_value());
  EXPECT_EQ(options.record_path, std::filesystem::path("r.pcapng"));
  EXPECT_DOUBLE_EQ(options.time_scale, 50.0);
  const auto can = parse_replay({"--replay", "c.log", "--can", "can:vcan1:6C2:6C3"});
  ASSERT_TRUE(can.has_value()) << can.error().message;
  EXPECT_EQ(can->options.can_interface, std::optional<std::string>("vcan1"));
}

TEST(ReplayOption, WhatARecordedDeviceHasNot_IsRefusedByName) {
  for (const std::vector<std::string_view>& extra :
       {std::vector<std::string_view>{"--scene", "s.yaml"}, {"--flash", "/tmp/f.flash"}, {"--flash-dir", "/tmp"},
        {"--reset-flash"}, {"--seed", "3"}}) {
    std::vector<std::string_view> arguments{"--replay", "scan.pcapng", "--tcp", "tcp:127.0.0.1:0"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto command = parse_replay(arguments);
    ASSERT_FALSE(command.has_value()) << extra.front();
    EXPECT_EQ(command.error().message, std::string(extra.front()) + ": conflicts with --replay (a recorded device " +
                                           "has no scene, flash, noise or faults)");
  }
}

// The monitor serves a recorded device too (its fault and object commands answer an error:
// daemon_replay_control_test.cpp).
TEST(ReplayOption, ControlAndEventLog_GoWithIt) {
  const auto command = parse_replay({"--replay", "scan.pcapng", "--tcp", "tcp:127.0.0.1:0", "--control", "/tmp/c.ctl",
                                     "--event-log", "/tmp/e.log"});
  ASSERT_TRUE(command.has_value()) << command.error().message;
  EXPECT_EQ(command->options.control_path, std::filesystem::path("/tmp/c.ctl"));
  EXPECT_EQ(command->options.event_log_path, std::filesystem::path("/tmp/e.log"));
}

TEST(ReplayOption, ItsSubOptionsNeedIt_AndAreChecked) {
  EXPECT_EQ(parse_replay({"--scene", "s.yaml", "--replay-port", "4000"}).error().message,
            "--replay-port: needs --replay CAPTURE");
  EXPECT_EQ(parse_replay({"--scene", "s.yaml", "--replay-transport", "tcp"}).error().message,
            "--replay-transport: needs --replay CAPTURE");
  EXPECT_EQ(parse_replay({"--replay", "s.pcapng", "--lpt", "lpt:pty:/tmp/l"}).error().message,
            "--replay: no endpoint: give --tcp tcp:HOST[:PORT], --serial serial:pty:PATH or --can can:IF");
  EXPECT_EQ(parse_replay({"--replay", "s.pcapng", "--replay-transport", "usb"}).error().message,
            "--replay-transport: must be tcp, serial or can");
  EXPECT_EQ(parse_replay({"--replay", "s.pcapng", "--replay-port", "0"}).error().message,
            "--replay-port: must be a TCP port from 1 to 65535");
  EXPECT_NE(usage_text("ldoem-emud").find("--replay CAPTURE"), std::string::npos);
}

}  // namespace
}  // namespace ldoem::daemon
