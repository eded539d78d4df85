// ldoem-hub over two real ldoem-emud devices, one with an encoder fault (D11): the asker gets
// ERR device_fault, every client gets `* OK FAULT device=bad`, and the healthy device goes on
// being served (docs/hub.md, "Device faults").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "ldoem/driver/scanner_device.hpp"
#include "ldoem/hub/hub_client.hpp"
#include "ldoem/hub/hub_server.hpp"
#include "scenario_device.hpp"

namespace ldoem::fault_scenarios {
namespace {

using namespace std::chrono_literals;

std::string minimal_scene() { return std::string(LDOEM_SOURCE_DIR) + "/scenes/minimal.yaml"; }

// ldoem-hub in this process on an ephemeral port, its loop on a thread stopped and joined on scope exit.
struct InProcessHub {
  hub::Hub hub;
  bool listening;
  std::thread loop;

  explicit InProcessHub(std::vector<hub::DeviceSlot> slots)
      : hub(settings(), std::move(slots)), listening(hub.listen()) {
    if (listening) loop = std::thread([this] { (void)hub.run(); });
  }
  ~InProcessHub() {
    if (!loop.joinable()) return;
    hub.request_stop();
    loop.join();
  }
  std::uint16_t port() const { return hub.port(); }

  static hub::HubSettings settings() {
    hub::HubSettings settings;
    settings.listen = hub::ListenAddress{"127.0.0.1", 0};
    return settings;
  }
};

TEST(FaultScenario, HubWithOneFaultedDevice_TellsEveryClient_AndServesTheOther) {
  // The minimal scene with an encoder that fails at power-up and stays failed.
  std::ifstream in(minimal_scene());
  std::stringstream text;
  text << in.rdbuf() << "faults:\n  - {kind: encoder_error}\n";
  const auto faulted_path = std::filesystem::temp_directory_path() / ("ldoem-encoder-" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(faulted_path) << text.str();
  std::string failure;
  auto good = start_scene(minimal_scene(), {}, &failure);
  ASSERT_TRUE(good) << failure;
  auto bad = start_scene(faulted_path.string(), {}, &failure);
  std::filesystem::remove(faulted_path);
  ASSERT_TRUE(bad) << failure;

  std::vector<hub::DeviceSlot> slots;
  slots.push_back({"good", driver::ScannerDevice::from_endpoints("good", driver::Endpoint{good->endpoint}, std::nullopt)});
  slots.push_back({"bad", driver::ScannerDevice::from_endpoints("bad", driver::Endpoint{bad->endpoint}, std::nullopt)});
  InProcessHub hub(std::move(slots));
  ASSERT_TRUE(hub.listening);

  const hub::ListenAddress address{"127.0.0.1", hub.port()};
  auto asker = hub::HubClient::connect(address, 5000ms);
  auto bystander = hub::HubClient::connect(address, 5000ms);
  ASSERT_TRUE(asker && bystander);
  const auto soon = [] { return driver::Clock::now() + 20s; };

  // INITIALIZE resets the faulted device to IDLE (DO_RESET 2); spinning it up fails at once.
  auto initialized = (*asker)->call("bad", hub::InitializeRequest{}, soon());
  ASSERT_TRUE(initialized);
  ASSERT_TRUE(initialized->ok) << hub::format_reply(*initialized);
  auto rotated = (*asker)->call("bad", hub::RotateCommand{}, soon());
  ASSERT_TRUE(rotated);
  EXPECT_FALSE(rotated->ok);
  EXPECT_EQ(rotated->error_kind, "device_fault") << hub::format_reply(*rotated);
  EXPECT_NE(rotated->error_message.find("status 0xB4"), std::string::npos) << rotated->error_message;

  // The bystander hears of it without asking (a notice may come already from INITIALIZE's
  // status; the first FAULT names the device and a final recovery).
  auto notice = (*bystander)->receive(soon());
  ASSERT_TRUE(notice) << driver::describe(notice.error());
  EXPECT_EQ(notice->id, "*");
  EXPECT_EQ(notice->command, "FAULT");
  EXPECT_EQ(notice->field("device"), "bad");
  EXPECT_EQ(notice->field("recovery"), "reset_device");

  // The healthy device is served all along.
  auto good_init = (*bystander)->call("good", hub::InitializeRequest{}, soon());
  ASSERT_TRUE(good_init);
  EXPECT_TRUE(good_init->ok) << hub::format_reply(*good_init);
  auto good_rotate = (*bystander)->call("good", hub::RotateCommand{}, soon());
  ASSERT_TRUE(good_rotate);
  EXPECT_TRUE(good_rotate->ok) << hub::format_reply(*good_rotate);
  EXPECT_EQ(good_rotate->field("mode"), "rotate");
  for (const auto& kept : (*bystander)->take_notices()) {
    EXPECT_NE(kept.field("device"), "good") << hub::format_reply(kept);
  }
}

// ldoem-scan through ldoem-hub (in-process here) over scenes/faults/power-cycle-during-profile:
// the hub's device loses its connection mid-scan; ldoem-scan --retries sees the retryable
// failure through the hub, re-initializes (the hub reconnects to the device) and completes
// every layer, and the cloud is written only then.
TEST(FaultScenario, PowerCycleThroughTheHub_LdoemScanRetriesAndCompletes) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ldoem-hub-cycle-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string lpt = (dir / "lpt").string();
  const std::string out = (dir / "scan.ply").string();
  std::string failure;
  auto scene = start_scene(scenario("power-cycle-during-profile"), {"--lpt", "lpt:pty:" + lpt}, &failure);
  ASSERT_TRUE(scene) << failure;
  const auto lpt_endpoint = driver::parse_endpoint("lpt:pty:" + lpt);
  ASSERT_TRUE(lpt_endpoint);
  std::vector<hub::DeviceSlot> slots;
  slots.push_back({"cycled", driver::ScannerDevice::from_endpoints("cycled", driver::Endpoint{scene->endpoint}, *lpt_endpoint)});
  InProcessHub hub(std::move(slots));
  ASSERT_TRUE(hub.listening);

  // 9 deg at 0.18 deg: 51 layers, about 15 s: the power cycle (5 s, 1.5 s off) comes mid-scan.
  auto scan = daemon::test::DaemonProcess::start_program(
      LDOEM_SCAN_PATH, {"--hub", "127.0.0.1:" + std::to_string(hub.port()), "--hub-device", "cycled", "--vertical-apex",
                        "9", "--retries", "3", "--timeout", "2", "--out", out});
  ASSERT_TRUE(scan);
  const auto status = scan->wait(150s);
  const std::string text = scan->stderr_text();
  ASSERT_EQ(status, std::optional<int>(0)) << text;
  EXPECT_NE(text.find("in 51 layers written"), std::string::npos) << text;
  EXPECT_NE(text.find("; retry 1 of 3"), std::string::npos) << text;
  EXPECT_NE(text.find("restarts after faults"), std::string::npos) << text;
  EXPECT_TRUE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ldoem::fault_scenarios
