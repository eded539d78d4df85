#include <gtest/gtest.h>

#include <array>
#include <chrono>

#include "ldoem/io/can_socket.hpp"
#include "vcan_fixture.hpp"

namespace ldoem::test {
namespace {

using namespace std::chrono_literals;

TEST(CanRawSocket, OpenVcan0_Succeeds) {
  auto socket = io::CanRawSocket::open(kVcan);
  ASSERT_TRUE(socket) << socket.error().message()
                      << " (run inside UML: scripts/uml/run.sh -- ctest -L vcan)";
  EXPECT_EQ(socket->interface_name(), "vcan0");
  EXPECT_GE(socket->fd(), 0);
}

TEST(CanRawSocket, FrameSentOnOneSocket_IsReceivedByAnother) {
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  LDOEM_ASSERT_OPEN_CAN(receiver, kVcan);
  const protocol::CanFrame frame = frame_of(0x6C0, {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08});

  auto sent = sender.send(frame);
  ASSERT_TRUE(sent) << sent.error().message();
  EXPECT_EQ(*sent, io::SendOutcome::sent);

  const auto frames = receive_frames(receiver, 1, 2s);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], frame);
}

TEST(CanRawSocket, FramesOfEveryLength_ArriveInOrderWithTheirBytes) {
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  LDOEM_ASSERT_OPEN_CAN(receiver, kVcan);
  std::vector<protocol::CanFrame> expected;
  for (std::uint8_t length = 0; length <= 8; ++length) {
    std::vector<std::uint8_t> bytes;
    for (std::uint8_t i = 0; i < length; ++i) {
      bytes.push_back(static_cast<std::uint8_t>(0xA0 + length * 8 + i));
    }
    expected.push_back(frame_of(0x100 + length, bytes));
    auto sent = sender.send(expected.back());
    ASSERT_TRUE(sent) << sent.error().message();
  }
  const auto frames = receive_frames(receiver, expected.size(), 2s);
  EXPECT_EQ(frames, expected);
}

TEST(CanRawSocket, SenderDoesNotReceiveItsOwnFrames) {
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  ASSERT_TRUE(sender.send(frame_of(0x6C1, {0x55})));
  auto own = sender.receive();
  ASSERT_TRUE(own) << own.error().message();
  EXPECT_FALSE(own->has_value());
}

TEST(CanRawSocket, KernelFilter_PassesOnlyTheRequestedId) {
  const std::array filters{io::exact_standard_id(0x6C0)};
  LDOEM_ASSERT_OPEN_CAN(receiver, kVcan, filters);
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  ASSERT_TRUE(sender.send(frame_of(0x6C1, {0xAA})));
  ASSERT_TRUE(sender.send(frame_of(0x123, {0xBB})));
  ASSERT_TRUE(sender.send(frame_of(0x6C0, {0xCC, 0xDD})));

  const auto frames = receive_frames(receiver, 1, 2s);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0], frame_of(0x6C0, {0xCC, 0xDD}));
  // Nothing else is queued behind it.
  auto next = receiver.receive();
  ASSERT_TRUE(next) << next.error().message();
  EXPECT_FALSE(next->has_value());
}

TEST(CanRawSocket, SetFiltersAfterOpen_ChangesWhatArrives) {
  LDOEM_ASSERT_OPEN_CAN(receiver, kVcan);
  const std::array filters{io::exact_standard_id(0x321)};
  auto changed = receiver.set_filters(filters);
  ASSERT_TRUE(changed) << changed.error().message();
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  ASSERT_TRUE(sender.send(frame_of(0x6C0, {0x01})));
  ASSERT_TRUE(sender.send(frame_of(0x321, {0x02})));
  const auto frames = receive_frames(receiver, 1, 2s);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].id, 0x321u);
}

TEST(CanRawSocket, FramesOnVcan1_DoNotReachVcan0) {
  LDOEM_ASSERT_OPEN_CAN(on_vcan1, "vcan1");
  LDOEM_ASSERT_OPEN_CAN(on_vcan0, kVcan);
  ASSERT_TRUE(on_vcan1.send(frame_of(0x6C0, {0x01})));
  const auto frames = receive_frames(on_vcan0, 1, 200ms);
  EXPECT_TRUE(frames.empty());
}

TEST(CanRawSocket, IdentifierOver11Bits_IsRejectedBeforeSending) {
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  protocol::CanFrame frame;
  frame.id = 0x800;
  auto sent = sender.send(frame);
  ASSERT_FALSE(sent);
  EXPECT_EQ(sent.error().error_number, EINVAL);
  EXPECT_NE(sent.error().message().find("11 bits"), std::string::npos) << sent.error().message();
}

TEST(CanRawSocket, LengthOver8_IsRejectedBeforeSending) {
  LDOEM_ASSERT_OPEN_CAN(sender, kVcan);
  protocol::CanFrame frame;
  frame.id = 0x6C0;
  frame.length = 9;
  auto sent = sender.send(frame);
  ASSERT_FALSE(sent);
  EXPECT_EQ(sent.error().error_number, EINVAL);
}

TEST(CanRawSocket, MissingInterface_GivesAnErrorNamingIt) {
  auto socket = io::CanRawSocket::open("vcan9");
  ASSERT_FALSE(socket);
  EXPECT_EQ(socket.error().error_number, ENODEV) << socket.error().message();
  EXPECT_EQ(socket.error().message(), "if_nametoindex vcan9: No such device");
}

}  // namespace
}  // namespace ldoem::test
