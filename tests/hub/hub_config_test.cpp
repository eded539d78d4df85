#include "ldoem/hub/hub_config.hpp"
#include "ldoem/hub/hub_options.hpp"

#include <gtest/gtest.h>

namespace ldoem::hub {
namespace {

TEST(HubConfig, FullFile_IsRead) {
  auto config = parse_hub_config(R"(
listen: 127.0.0.1:49300
max_age_ms: 20
devices:
  - name: left
    scanner: tcp:127.0.0.1:49152
    lpt: lpt:pty:/tmp/ldoem-lpt
    stepper: { rate_hz: 400 }
    request_timeout_ms: 2000
    reconnect: { attempts: 30, interval_ms: 250, backoff: 2, max_interval_ms: 4000 }
  - name: right
    scanner: can:vcan0
)");
  ASSERT_TRUE(config) << config.error();
  EXPECT_EQ(config->listen, (ListenAddress{"127.0.0.1", 49300}));
  EXPECT_EQ(config->max_age, std::chrono::milliseconds(20));
  ASSERT_EQ(config->devices.size(), 2u);
  EXPECT_EQ(config->devices[0].name, "left");
  EXPECT_EQ(config->devices[0].stepper.step_rate_hz, 400.0);
  EXPECT_EQ(config->devices[0].request_timeout, std::chrono::milliseconds(2000));
  EXPECT_EQ(config->devices[0].reconnect, (driver::ReconnectPolicy{30, std::chrono::milliseconds(250), 2.0,
                                                                     std::chrono::milliseconds(4000)}));
  EXPECT_EQ(config->devices[1].reconnect, driver::ReconnectPolicy{});  // libldoem's default
  EXPECT_TRUE(config->devices[0].lpt);
  EXPECT_FALSE(config->devices[1].lpt);
  EXPECT_TRUE(std::holds_alternative<driver::CanEndpoint>(config->devices[1].scanner));
}

TEST(HubConfig, Mistakes_AreOneLineErrors) {
  const char* bad[] = {
      "devices: []",
      "devices:\n  - name: a\n",
      "devices:\n  - name: a\n    scanner: bogus:x\n",
      "devices:\n  - name: a\n    scanner: lpt:pty:/x\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    lpt: tcp:h\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n  - name: a\n    scanner: tcp:h\n",
      "devices:\n  - name: a b\n    scanner: tcp:h\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    colour: red\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    stepper: { rate_hz: -1 }\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    reconnect: { attempts: 0 }\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    reconnect: { backoff: 0.5 }\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    reconnect: { interval_ms: -5 }\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    reconnect: { tries: 3 }\n",
      "devices:\n  - name: a\n    scanner: tcp:h\n    reconnect: 3\n",
      "listen: nowhere\ndevices:\n  - name: a\n    scanner: tcp:h\n",
      "devices: [ unclosed",
  };
  for (const char* text : bad) {
    auto config = parse_hub_config(text);
    EXPECT_FALSE(config) << text;
    if (!config) {
      EXPECT_EQ(config.error().find('\n'), std::string::npos) << config.error();
    }
  }
}

TEST(ListenAddress, Forms_AreParsed) {
  EXPECT_EQ(parse_listen_address("127.0.0.1:49200").value(), (ListenAddress{"127.0.0.1", 49200}));
  EXPECT_EQ(parse_listen_address(":0").value(), (ListenAddress{"127.0.0.1", 0}));
  EXPECT_EQ(parse_listen_address("[::1]:5").value(), (ListenAddress{"::1", 5}));
  EXPECT_FALSE(parse_listen_address("host:70000"));
  EXPECT_FALSE(parse_listen_address("host"));
}

TEST(HubCommandLine, Options_AreParsed) {
  auto line = parse_hub_command_line({"--config", "hub.yaml", "--listen", "127.0.0.1:1", "--max-age-ms", "0",
                                      "--max-clients", "8", "--queue", "4"});
  ASSERT_TRUE(line) << line.error();
  EXPECT_EQ(line->config_path, "hub.yaml");
  EXPECT_EQ(line->max_age, std::chrono::milliseconds(0));
  EXPECT_EQ(line->max_clients, 8u);
  EXPECT_EQ(line->queue_capacity, 4u);
  EXPECT_FALSE(parse_hub_command_line({}));
  EXPECT_FALSE(parse_hub_command_line({"--config"}));
  EXPECT_FALSE(parse_hub_command_line({"--config", "a", "--queue", "0"}));
  EXPECT_FALSE(parse_hub_command_line({"--config", "a", "--what", "1"}));
  EXPECT_TRUE(parse_hub_command_line({"--help"})->help);
}

}  // namespace
}  // namespace ldoem::hub
