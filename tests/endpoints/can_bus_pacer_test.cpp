// D9 bus_timing: our CAN frames leave at the configured bit rate (D1 BITRATE), in virtual time.
#include "ldoem/endpoints/can_bus_pacer.hpp"

#include <gtest/gtest.h>

#include "ldoem/endpoints/isotp_channel.hpp"

namespace ldoem::endpoints {
namespace {

using namespace std::chrono_literals;

// A frame of `length` zero bytes: the pacer only looks at the length.
protocol::CanFrame zero_filled_frame(std::uint32_t id, std::size_t length) {
  protocol::CanFrame out;
  out.id = id;
  out.length = static_cast<std::uint8_t>(length);
  return out;
}

TEST(CanBitRate, D1Codes_MapToBitsPerSecondAndUnknownCodesToOneMegabit) {
  EXPECT_EQ(can_bit_rate_bps(1), 125'000u);
  EXPECT_EQ(can_bit_rate_bps(2), 250'000u);
  EXPECT_EQ(can_bit_rate_bps(3), 500'000u);
  EXPECT_EQ(can_bit_rate_bps(4), 1'000'000u);
  EXPECT_EQ(can_bit_rate_bps(0), 1'000'000u);
  EXPECT_EQ(can_bit_rate_bps(9), 1'000'000u);
}

TEST(CanFrameDuration, NominalBitsWithoutStuffing_AtTheBitRate) {
  EXPECT_EQ(can_frame_duration(8, 1'000'000), 111us);  // 47 + 64 bits
  EXPECT_EQ(can_frame_duration(0, 1'000'000), 47us);
  EXPECT_EQ(can_frame_duration(3, 125'000), 568us);  // 71 bits at 8 us
  EXPECT_EQ(can_frame_duration(8, 250'000), 4 * can_frame_duration(8, 1'000'000));
}

TEST(CanBusPacer, FramesLeaveBackToBackWhenTheirLastBitIsOnTheBus) {
  CanBusPacer bus(1'000'000);
  bus.push(SimTime::zero(), zero_filled_frame(0x6C1, 8));
  bus.push(SimTime::zero(), zero_filled_frame(0x6C1, 2));
  EXPECT_EQ(bus.deadline(), std::optional<SimTime>(111us));
  EXPECT_TRUE(bus.take_due(110us).empty());
  EXPECT_TRUE(bus.pending_for(0x6C1));
  EXPECT_EQ(bus.take_due(111us).size(), 1u);
  EXPECT_EQ(bus.deadline(), std::optional<SimTime>(111us + 63us));  // 47 + 16 bits, right behind
  EXPECT_EQ(bus.take_due(1s).size(), 1u);
  EXPECT_TRUE(bus.empty());
  EXPECT_FALSE(bus.pending_for(0x6C1));
  EXPECT_FALSE(bus.deadline().has_value());
}

TEST(CanBusPacer, IdleBus_StartsAFrameWhenItIsPushed) {
  CanBusPacer bus(500'000);
  bus.push(10ms, zero_filled_frame(0x6C1, 8));
  EXPECT_EQ(bus.deadline(), std::optional<SimTime>(10ms + 222us));
  EXPECT_FALSE(bus.pending_for(0x6C3));
}

TEST(CanBusPacer, NewBitRate_AppliesToFramesPushedAfterIt) {
  CanBusPacer bus(1'000'000);
  bus.push(SimTime::zero(), zero_filled_frame(0x6C1, 8));
  bus.set_bit_rate(125'000);
  bus.push(SimTime::zero(), zero_filled_frame(0x6C1, 8));
  EXPECT_EQ(bus.bus_free_at(), 111us + 888us);
}

// One telegram of `bytes` from the LD through its ISO-TP channel onto a paced bus, to a host
// that answers the first frame's flow control (BS 0, STmin 0) the moment it arrives. Returns
// the simulated time the host has the whole telegram; virtual time jumps from deadline to deadline.
std::optional<SimTime> transfer_time(std::uint32_t bit_rate_bps, std::size_t bytes) {
  IsoTpChannel ld(IsoTpChannelConfig{CanIdPair{0x6C0, 0x6C1}});
  IsoTpChannel host(IsoTpChannelConfig{CanIdPair{0x6C1, 0x6C0}});
  CanBusPacer bus(bit_rate_bps);
  const protocol::Bytes profile(bytes, 0x5A);
  SimTime now = SimTime::zero();
  for (const auto& f : ld.send(now, profile).frames) bus.push(now, f);
  while (const auto due = bus.deadline()) {
    now = *due;
    for (const auto& f : bus.take_due(now)) {
      auto at_host = host.on_frame(now, f);
      for (const auto& flow_control : at_host.frames) {  // the host's frames are not paced
        for (const auto& next : ld.on_frame(now, flow_control).frames) bus.push(now, next);
      }
      if (!at_host.telegrams.empty()) {
        if (at_host.telegrams.front() != profile) return std::nullopt;
        return now;
      }
    }
  }
  return std::nullopt;
}

TEST(CanBusPacer, ProfileOf5800Bytes_TakesItsFramesBitTimeAndFourTimesAsLongAt250k) {
  // D1: over 4095 bytes the first frame uses the 32-bit length escape: 8 bytes carrying 2 of
  // the telegram's. The other 5798 bytes go in 828 consecutive frames of 7 (DLC 8) and one of
  // 2 (DLC 3): 829 frames of 111 bits and one of 71 bits = 92 090 bits.
  constexpr std::int64_t kBits = 829 * 111 + 71;
  const auto at_1m = transfer_time(1'000'000, 5800);
  ASSERT_TRUE(at_1m.has_value());
  EXPECT_EQ(*at_1m, SimTime(kBits * 1000));  // 1 us per bit
  const auto at_250k = transfer_time(250'000, 5800);
  ASSERT_TRUE(at_250k.has_value());
  EXPECT_EQ(*at_250k, 4 * *at_1m);
  EXPECT_EQ(transfer_time(125'000, 5800), std::optional<SimTime>(8 * *at_1m));
}

}  // namespace
}  // namespace ldoem::endpoints
