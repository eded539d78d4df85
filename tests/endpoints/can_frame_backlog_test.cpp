// Issue 11: the CAN backlog (frames the interface's queue refused) is bounded; a batch that does
// not fit is dropped whole and counted, frames already queued stay and leave in order.
#include <gtest/gtest.h>

#include <vector>

#include "ldoem/endpoints/can_frame_backlog.hpp"

namespace ldoem::endpoints {
namespace {

std::vector<protocol::CanFrame> frames(std::uint8_t first, std::size_t count) {
  std::vector<protocol::CanFrame> batch;
  for (std::size_t i = 0; i < count; ++i) {
    batch.push_back(*protocol::make_can_frame(0x6C1, protocol::Bytes{static_cast<std::uint8_t>(first + i)}));
  }
  return batch;
}

TEST(CanFrameBacklog, BatchThatDoesNotFit_IsDroppedWholeAndCounted) {
  CanFrameBacklog backlog(5);
  EXPECT_TRUE(backlog.push(frames(1, 3)));
  EXPECT_FALSE(backlog.push(frames(10, 3)));  // 6 > 5: the newest batch goes
  EXPECT_EQ(backlog.size(), 3u);
  EXPECT_EQ(backlog.dropped(), 3u);
  EXPECT_TRUE(backlog.push(frames(20, 2)));   // exactly full
  for (const std::uint8_t expected : {1, 2, 3, 20, 21}) {
    ASSERT_FALSE(backlog.empty());
    EXPECT_EQ(backlog.front().data[0], expected);
    backlog.pop_front();
  }
  EXPECT_TRUE(backlog.empty());
}

// A bus that never takes a frame (nobody acknowledges): a host asking for profiles forever
// costs at most the bound, not memory without end.
TEST(CanFrameBacklog, EndlessFramesOnADeadBus_StayWithinTheBound) {
  CanFrameBacklog backlog;
  for (int profile = 0; profile < 1000; ++profile) (void)backlog.push(frames(0, 832));
  EXPECT_LE(backlog.size(), kMaxCanBacklogFrames);
  EXPECT_EQ(backlog.dropped(), 1000u * 832u - backlog.size());
}

}  // namespace
}  // namespace ldoem::endpoints
