// Hubs with fake devices: 16 concurrent clients on 3 devices without mixed or lost replies,
// per-device serialisation, the freshness rule, and errors going to the client that caused them.
#include "ldoem/hub/hub_server.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <thread>

#include "fake_hub.hpp"
#include "ldoem/hub/hub_client.hpp"

namespace ldoem::hub {
namespace {

using driver::Clock;
using hub_testing::FakeDevice;
using hub_testing::RunningHub;
using hub_testing::soon;
using std::chrono::milliseconds;

TEST(Hub, SixteenClientsOnThreeDevices_EveryReplyReachesItsSenderUnmixed) {
  constexpr int kClients = 16;
  constexpr int kRequestsPerClient = 60;
  HubSettings settings = RunningHub::settings_with(milliseconds(0), 1024);
  settings.max_in_flight = kRequestsPerClient;  // every client pipelines all its requests
  RunningHub running(3, settings);
  std::vector<std::string> frontend_ids(kClients);
  std::vector<std::string> failures(kClients);
  std::vector<std::thread> threads;
  for (int c = 0; c < kClients; ++c) {
    threads.emplace_back([&, c] {
      auto client = running.client();
      frontend_ids[c] = client->frontend_id();
      // All requests are written first (pipelined), then every reply is read.
      std::map<std::string, std::pair<int, int>> expected;  // id -> device number, frequency
      for (int k = 0; k < kRequestsPerClient; ++k) {
        const int device = (c + k) % 3 + 1;
        const int hz = (c * kRequestsPerClient + k) % 250 + 1;
        const std::string id = "c" + std::to_string(c) + "." + std::to_string(k);
        expected[id] = {device, hz};
        const std::string line = format_request(HubRequest{id, "dev" + std::to_string(device), RotateCommand{static_cast<std::uint16_t>(hz)}});
        if (!client->send_line(line, soon())) {
          failures[c] = "send failed";
          return;
        }
      }
      for (int k = 0; k < kRequestsPerClient; ++k) {
        auto reply = client->receive(soon());
        if (!reply) {
          failures[c] = "lost a reply: " + driver::describe(reply.error());
          return;
        }
        const auto found = expected.find(reply->id);
        if (found == expected.end()) {
          failures[c] = "foreign or repeated reply " + format_reply(*reply);
          return;
        }
        const auto status = status_from(*reply);
        if (!reply->ok || !status || status->unpublished[0] != found->second.first ||
            status->unpublished[1] != found->second.second ||
            reply->field("handler") != "B" + std::to_string(found->second.first)) {
          failures[c] = "mixed reply " + format_reply(*reply);
          return;
        }
        expected.erase(found);
      }
    });
  }
  for (auto& thread : threads) {
    thread.join();
  }
  for (int c = 0; c < kClients; ++c) {
    EXPECT_EQ(failures[c], "") << "client " << c;
  }
  EXPECT_EQ(std::set<std::string>(frontend_ids.begin(), frontend_ids.end()).size(), static_cast<std::size_t>(kClients));
  int calls = 0;
  for (FakeDevice* device : running.devices) {
    EXPECT_EQ(device->overlaps.load(), 0) << "a BEMH let two calls into its device at once";
    calls += device->calls.load();
  }
  EXPECT_EQ(calls, kClients * kRequestsPerClient);
}

TEST(Hub, FullQueue_AnswersBusyAndStillAnswersEveryRequestOnce) {
  RunningHub running(1, milliseconds(0), 2);
  auto client = running.client();
  constexpr int kBurst = 50;
  std::unique_lock hold(running.devices[0]->gate);  // the first job blocks, two more fit the queue
  ASSERT_TRUE(client->send_line("b0 dev1 ROTATE 7", soon()));
  while (running.devices[0]->rotate_started.load() == 0) {
    std::this_thread::yield();
  }
  for (int k = 1; k < kBurst; ++k) {
    ASSERT_TRUE(client->send_line("b" + std::to_string(k) + " dev1 ROTATE 7", soon()));
  }
  for (int k = 0; k < kBurst - 3; ++k) {
    auto reply = client->receive(soon());
    ASSERT_TRUE(reply);
    EXPECT_FALSE(reply->ok);
    EXPECT_EQ(reply->error_kind, "busy");
  }
  hold.unlock();
  for (int k = 0; k < 3; ++k) {
    auto reply = client->receive(soon());
    ASSERT_TRUE(reply);
    EXPECT_TRUE(reply->ok) << format_reply(*reply);
  }
  EXPECT_FALSE(client->receive(driver::Clock::now() + milliseconds(100)));
  EXPECT_EQ(running.devices[0]->calls.load(), 3);
}

TEST(Hub, Devices_ListsNamesWithHandlerIds) {
  RunningHub running(2);
  auto client = running.client();
  auto reply = client->call("*", DevicesCommand{}, soon());
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->field("devices"), "dev1:B1,dev2:B2");
}

TEST(Hub, FreshData_IsAnsweredFromTheCacheUntilTheDeviceChanges) {
  RunningHub running(1, milliseconds(60000));
  auto client = running.client();
  auto first = client->call("dev1", StatusCommand{}, soon());
  ASSERT_TRUE(first && first->ok);
  EXPECT_EQ(first->field("source"), "device");
  auto second = client->call("dev1", StatusCommand{}, soon());
  ASSERT_TRUE(second && second->ok);
  EXPECT_EQ(second->field("source"), "cache");
  EXPECT_EQ(second->field("handler"), "B1");
  EXPECT_EQ(status_from(*second), status_from(*first));
  auto forced = client->call("dev1", StatusCommand{milliseconds(0)}, soon());
  ASSERT_TRUE(forced);
  EXPECT_EQ(forced->field("source"), "device");

  auto profile = client->call("dev1", ProfileCommand{}, soon());
  ASSERT_TRUE(profile && profile->ok);
  EXPECT_EQ(profile->field("source"), "device");
  auto cached = client->call("dev1", ProfileCommand{}, soon());
  ASSERT_TRUE(cached);
  EXPECT_EQ(cached->field("source"), "cache");
  EXPECT_EQ(profile_from(*cached)->profile.profile_count, 1);

  // A move makes the latest profile stale: the next one comes from the device, at the new tilt.
  ASSERT_TRUE(client->call("dev1", MotorMove{3, TiltDirection::increasing, StepMode::full_step, {}}, soon()));
  auto after_move = client->call("dev1", ProfileCommand{}, soon());
  ASSERT_TRUE(after_move && after_move->ok);
  EXPECT_EQ(after_move->field("source"), "device");
  EXPECT_EQ(profile_from(*after_move)->tilt.half_steps, 6);
  EXPECT_EQ(profile_from(*after_move)->profile.profile_count, 2);
}

TEST(Hub, PipelinedMoveThenProfile_NeverGetsTheProfileFromBeforeTheMove) {
  RunningHub running(1, milliseconds(60000));
  auto client = running.client();
  ASSERT_TRUE(client->call("dev1", ProfileCommand{}, soon()));  // fills the cache
  ASSERT_TRUE(client->send_line("m dev1 MOVEMOTOR 5 down full", soon()));
  ASSERT_TRUE(client->send_line("p dev1 GET2DPROFILE", soon()));
  std::map<std::string, HubReply> replies;
  for (int i = 0; i < 2; ++i) {
    auto reply = client->receive(soon());
    ASSERT_TRUE(reply);
    replies[reply->id] = *reply;
  }
  EXPECT_EQ(replies["p"].field("source"), "device");
  EXPECT_EQ(profile_from(replies["p"])->tilt.half_steps, -10);
}

TEST(Hub, DeviceError_GoesOnlyToTheClientThatAsked) {
  RunningHub running(2);
  auto asker = running.client();
  auto bystander = running.client();
  running.devices[0]->fail_status.store(true);
  auto reply = asker->call("dev1", StatusCommand{}, soon());
  ASSERT_TRUE(reply);
  EXPECT_FALSE(reply->ok);
  EXPECT_EQ(reply->error_kind, "timeout");
  EXPECT_NE(reply->error_message.find("B1"), std::string::npos);
  // The bystander's next reply is its own.
  auto own = bystander->call("dev2", StatusCommand{}, soon());
  ASSERT_TRUE(own);
  EXPECT_TRUE(own->ok);
  EXPECT_EQ(own->id, "c1");
  EXPECT_FALSE(bystander->receive(Clock::now() + milliseconds(100)));
}

TEST(Hub, BadRequests_AreAnsweredWithTheirId) {
  RunningHub running(1);
  auto client = running.client();
  ASSERT_TRUE(client->send_line("q1 nosuch STATUS", soon()));
  ASSERT_TRUE(client->send_line("q2 dev1 FLY", soon()));
  ASSERT_TRUE(client->send_line("q3 dev1 MOVEMOTOR x up full", soon()));
  ASSERT_TRUE(client->send_line(std::string(2000, 'x'), soon()));
  ASSERT_TRUE(client->send_line("q4 dev1 STATUS", soon()));
  const std::pair<const char*, const char*> expected[] = {
      {"q1", "unknown_device"}, {"q2", "unknown_command"}, {"q3", "bad_request"}, {"-", "bad_request"}};
  for (const auto& [id, kind] : expected) {
    auto reply = client->receive(soon());
    ASSERT_TRUE(reply);
    EXPECT_EQ(reply->id, id);
    EXPECT_FALSE(reply->ok);
    EXPECT_EQ(reply->error_kind, kind);
  }
  auto fine = client->receive(soon());
  ASSERT_TRUE(fine);
  EXPECT_EQ(fine->id, "q4");
  EXPECT_TRUE(fine->ok);
}

TEST(Hub, HubDevice_DrivesAFakeDeviceThroughTheHub) {
  RunningHub running(1);
  HubDevice device(running.client(), "dev1");
  auto info = device.initialize({});
  ASSERT_TRUE(info) << driver::describe(info.error());
  ASSERT_EQ(info->identification.size(), 1u);
  EXPECT_EQ(info->identification[0].text, "fake 1");
  auto rotate = device.rotate(12);
  ASSERT_TRUE(rotate);
  EXPECT_EQ(rotate->unpublished[1], 12);
  auto moved = device.move_motor(MotorMove{4, TiltDirection::decreasing, StepMode::half_step, 500.0});
  ASSERT_TRUE(moved);
  EXPECT_EQ(moved->half_steps, -4);
  auto profile = device.get_profile(milliseconds(1000));
  ASSERT_TRUE(profile);
  EXPECT_EQ(profile->tilt.half_steps, -4);
  running.devices[0]->fail_status.store(true);
  auto status = device.status();
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().kind, ErrorKind::timeout);
}

}  // namespace
}  // namespace ldoem::hub
