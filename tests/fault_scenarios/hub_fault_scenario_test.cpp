// ldoem-hub over two real ldoem-emud devices, one with an encoder fault (D11): the asker gets
// ERR device_fault, every client gets `* OK FAULT device=bad`, and the healthy device goes on
// being served (docs/hub.md, "Device faults").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "ldoem/hub/hub_client.hpp"
#include "ldoem/hub/hub_server.hpp"
#include "ldoem/hub/scanner_device.hpp"
#include "scenario_device.hpp"

namespace ldoem::fault_scenarios {
namespace {

using namespace std::chrono_literals;

std::string minimal_scene() { return std::string(LDOEM_SOURCE_DIR) + "/scenes/minimal.yaml"; }

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
  slots.push_back({"good", hub::ScannerDevice::from_endpoints("good", driver::Endpoint{good->endpoint}, std::nullopt)});
  slots.push_back({"bad", hub::ScannerDevice::from_endpoints("bad", driver::Endpoint{bad->endpoint}, std::nullopt)});
  hub::HubSettings settings;
  settings.listen = hub::ListenAddress{"127.0.0.1", 0};
  hub::Hub hub(settings, std::move(slots));
  ASSERT_TRUE(hub.listen());
  std::thread loop([&hub] { (void)hub.run(); });
  struct Stop {
    hub::Hub& hub;
    std::thread& loop;
    ~Stop() {
      hub.request_stop();
      loop.join();
    }
  } stop{hub, loop};

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

}  // namespace
}  // namespace ldoem::fault_scenarios
