// D7: simulated time from the wall clock times the scale, or a virtual clock that jumps.
#include <gtest/gtest.h>

#include <vector>

#include "ldoem/daemon/sim_clock.hpp"

namespace ldoem::daemon {
namespace {

using namespace std::chrono_literals;

const WallTime kStart = WallTime(100s);

TEST(SimClock, Scaled_MultipliesWallTimeSinceStart) {
  SimClock clock = SimClock::scaled(kStart, 2.0);
  EXPECT_EQ(clock.now(kStart), SimTime(0));
  EXPECT_EQ(clock.now(kStart + 1s), SimTime(2s));
  EXPECT_EQ(clock.now(kStart + 1500ms), SimTime(3s));
}

TEST(SimClock, Scaled_WallDeadlineIsNeverEarly) {
  const SimClock clock = SimClock::scaled(kStart, 3.0);
  const SimTime due = SimTime(1000000001);  // not a multiple of 3
  const WallTime wall = clock.wall_deadline(due, kStart);
  SimClock copy = clock;
  EXPECT_GE(copy.now(wall), due);
  EXPECT_LT(copy.now(wall - 1ns), due + 3ns);
}

TEST(SimClock, Scaled_NeverGoesBackwards) {
  SimClock clock = SimClock::scaled(kStart, 1.0);
  EXPECT_EQ(clock.now(kStart + 2s), SimTime(2s));
  EXPECT_EQ(clock.now(kStart + 1s), SimTime(2s));  // a late reading of an earlier wall time
  clock.advance_to(5s);
  EXPECT_EQ(clock.now(kStart + 3s), SimTime(5s));
}

TEST(SimClock, Virtual_MovesOnlyWhenAdvanced) {
  SimClock clock = SimClock::virtual_clock();
  EXPECT_TRUE(clock.is_virtual());
  EXPECT_EQ(clock.now(kStart + 10s), SimTime(0));
  clock.advance_to(7s);
  EXPECT_EQ(clock.now(kStart), SimTime(7s));
  clock.advance_to(3s);
  EXPECT_EQ(clock.now(kStart), SimTime(7s));
  EXPECT_EQ(clock.wall_deadline(100s, kStart), kStart);  // due at once
}

// Issue 11: a scale far outside the options' range (1e-6..1e6) saturates at 146 years instead
// of overflowing the conversion to int64 nanoseconds (undefined behaviour: on x86 the result was
// INT64_MIN, a deadline in the past and a clock that never moved).
TEST(SimClock, ExtremeScales_SaturateInsteadOfOverflowing) {
  const SimClock slow = SimClock::scaled(kStart, 1e-12);
  const WallTime far = slow.wall_deadline(SimTime(1h), kStart);
  EXPECT_GT(far, kStart + std::chrono::hours(24 * 365 * 100));
  SimClock fast = SimClock::scaled(kStart, 1e12);
  EXPECT_GT(fast.now(kStart + 1000000s), SimTime(std::chrono::hours(24 * 365 * 100)));
}

TEST(DeadlineQueue, PopsInTimeThenInsertionOrder) {
  DeadlineQueue queue;
  std::vector<int> fired;
  queue.add(2s, [&](SimTime) { fired.push_back(2); });
  queue.add(1s, [&](SimTime) { fired.push_back(1); });
  queue.add(2s, [&](SimTime) { fired.push_back(3); });
  EXPECT_EQ(queue.earliest(), std::optional<SimTime>(1s));
  EXPECT_FALSE(queue.pop_due(500ms).has_value());
  while (auto entry = queue.pop_due(2s)) entry->second(2s);
  EXPECT_EQ(fired, (std::vector<int>{1, 2, 3}));
  EXPECT_FALSE(queue.earliest().has_value());
}

TEST(DeadlineQueue, ActionMayAddADeadlineDueAtOnce) {
  DeadlineQueue queue;
  int fired = 0;
  queue.add(1s, [&](SimTime now) {
    ++fired;
    queue.add(now, [&](SimTime) { ++fired; });
  });
  while (auto entry = queue.pop_due(1s)) entry->second(1s);
  EXPECT_EQ(fired, 2);
}

}  // namespace
}  // namespace ldoem::daemon
