// A faulted device behind the hub (D11, docs/hub.md "Device faults"): the asker gets its ERR,
// every client gets one `* OK FAULT` notice, the other device goes on being served, and a
// later healthy reply is announced with `* OK RECOVERED`.
#include <gtest/gtest.h>

#include "fake_hub.hpp"
#include "ldoem/hub/hub_client.hpp"
#include "ldoem/hub/hub_server.hpp"

namespace ldoem::hub {
namespace {

using driver::Clock;
using hub_testing::RunningHub;
using hub_testing::soon;
using std::chrono::milliseconds;

TEST(HubFaults, OneFaultedDevice_EveryClientHearsOfIt_AndTheOtherDeviceIsServed) {
  RunningHub running(2);
  auto asker = running.client();
  auto bystander = running.client();
  running.devices[0]->motor_fault.store(true);

  auto rotated = asker->call("dev1", RotateCommand{}, soon());
  ASSERT_TRUE(rotated);
  EXPECT_FALSE(rotated->ok);
  EXPECT_EQ(rotated->error_kind, "device_fault");
  EXPECT_NE(rotated->error_message.find("status 0xB4"), std::string::npos) << rotated->error_message;

  // The bystander asked nothing of dev1 and still hears of its fault.
  auto notice = bystander->receive(soon());
  ASSERT_TRUE(notice);
  EXPECT_EQ(notice->id, "*");
  EXPECT_TRUE(notice->ok);
  EXPECT_EQ(notice->command, "FAULT");
  EXPECT_EQ(notice->field("device"), "dev1");
  EXPECT_EQ(notice->field("handler"), "B1");
  EXPECT_EQ(notice->field("kind"), "device_fault");
  EXPECT_EQ(notice->field("recovery"), "reset_device");
  EXPECT_EQ(notice->field("status_byte"), "180");
  EXPECT_NE(notice->field("detail")->find("motor fault, sensor mode ERROR"), std::string::npos);
  // The asker got the same notice, kept aside by call().
  const auto asker_notices = asker->take_notices();
  ASSERT_EQ(asker_notices.size(), 1u);
  EXPECT_EQ(asker_notices[0], *notice);

  // The other device is served as before, while dev1 stays faulted.
  auto other = bystander->call("dev2", StatusCommand{}, soon());
  ASSERT_TRUE(other);
  EXPECT_TRUE(other->ok);
  EXPECT_EQ(other->field("mode"), "rotate");
  // STATUS of the faulted device answers (mode=error) without a second notice: it is not news.
  auto faulted = asker->call("dev1", StatusCommand{}, soon());
  ASSERT_TRUE(faulted);
  EXPECT_TRUE(faulted->ok);
  EXPECT_EQ(faulted->field("mode"), "error");
  EXPECT_EQ(faulted->field("motor"), "fault");
  EXPECT_TRUE(asker->take_notices().empty());

  // The fault goes (a reset, a stall that ended): the next healthy reply is announced.
  running.devices[0]->motor_fault.store(false);
  auto healthy = asker->call("dev1", StatusCommand{}, soon());
  ASSERT_TRUE(healthy);
  EXPECT_TRUE(healthy->ok);
  const auto recovered = asker->take_notices();
  ASSERT_EQ(recovered.size(), 1u);
  EXPECT_EQ(recovered[0].command, "RECOVERED");
  EXPECT_EQ(recovered[0].field("device"), "dev1");
  auto bystander_recovered = bystander->receive(soon());
  ASSERT_TRUE(bystander_recovered);
  EXPECT_EQ(bystander_recovered->command, "RECOVERED");
}

TEST(HubFaults, ATimeoutIsTheAskersAlone_NoNotice) {
  RunningHub running(2);
  auto asker = running.client();
  auto bystander = running.client();
  running.devices[0]->fail_status.store(true);
  auto reply = asker->call("dev1", StatusCommand{}, soon());
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->error_kind, "timeout");
  EXPECT_TRUE(asker->take_notices().empty());
  EXPECT_FALSE(bystander->receive(Clock::now() + milliseconds(200)));
}

}  // namespace
}  // namespace ldoem::hub
