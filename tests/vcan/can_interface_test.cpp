#include "ldoem/io/can_interface.hpp"

#include <gtest/gtest.h>

#include "child_process.hpp"

namespace ldoem::test {
namespace {

TEST(CheckCanInterface, Vcan0_IsUpWithoutControllerState) {
  auto status = io::check_can_interface("vcan0");
  ASSERT_TRUE(status) << status.error().message()
                      << " (run inside UML: scripts/uml/run.sh -- ctest -L vcan)";
  EXPECT_GT(status->index, 0);
  // vcan has no CAN controller, so no error state: that is fine, not a failure.
  EXPECT_FALSE(status->controller_state.has_value());
}

TEST(CheckCanInterface, MissingInterface_SaysItDoesNotExist) {
  auto status = io::check_can_interface("vcan9");
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().error_number, ENODEV);
  EXPECT_EQ(status.error().message(), "can: interface vcan9 does not exist");
}

TEST(CheckCanInterface, Loopback_IsNotACanInterface) {
  auto status = io::check_can_interface("lo");
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().error_number, EINVAL);
  EXPECT_EQ(status.error().message(), "can: interface lo is not a CAN interface");
}

TEST(CheckCanInterface, InterfaceTakenDown_SaysItIsDown) {
  // A private interface, so that no other test sees vcan0/vcan1 go down.
  ASSERT_EQ(run_program({"ip", "link", "add", "dev", "ldoemdown0", "type", "vcan"}), 0);
  auto status = io::check_can_interface("ldoemdown0");
  ASSERT_EQ(run_program({"ip", "link", "del", "dev", "ldoemdown0"}), 0);
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().error_number, ENETDOWN);
  EXPECT_EQ(status.error().message(), "can: interface ldoemdown0 is down");
}

TEST(SetCanBitrate, OnVcan_FailsBecauseVcanHasNoBitTiming) {
  auto result = io::set_can_bitrate("vcan0", 1'000'000);
  ASSERT_FALSE(result);
  EXPECT_NE(result.error().message().find("can_set_bitrate vcan0"), std::string::npos)
      << result.error().message();
}

}  // namespace
}  // namespace ldoem::test
