#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>

#include "ldoem/driver/stop_signals.hpp"

namespace ldoem::driver {
namespace {

// Restores the thread's signal mask and dispositions, so the test leaves the process as it was.
class StopSignalsTest : public ::testing::Test {
 protected:
  void SetUp() override { ::pthread_sigmask(SIG_SETMASK, nullptr, &saved_mask_); }
  void TearDown() override { ::pthread_sigmask(SIG_SETMASK, &saved_mask_, nullptr); }

 private:
  sigset_t saved_mask_{};
};

bool readable(int fd) {
  pollfd entry{fd, POLLIN, 0};
  return ::poll(&entry, 1, 0) == 1;
}

TEST_F(StopSignalsTest, NothingPending_TakesZeroWithoutBlocking) {
  auto signals = StopSignals::block_and_open();
  ASSERT_TRUE(signals) << describe(signals.error());
  EXPECT_FALSE(readable(signals->fd()));
  EXPECT_EQ(signals->take_pending(), 0);
}

TEST_F(StopSignalsTest, SigtermAndSigint_ArriveOnTheDescriptorNotAsDeath) {
  auto signals = StopSignals::block_and_open();
  ASSERT_TRUE(signals);
  ASSERT_EQ(::raise(SIGTERM), 0);  // blocked: it waits on the descriptor instead of ending us
  EXPECT_TRUE(readable(signals->fd()));
  EXPECT_EQ(signals->take_pending(), SIGTERM);
  EXPECT_EQ(signals->take_pending(), 0);
  ASSERT_EQ(::raise(SIGINT), 0);
  EXPECT_EQ(signals->take_pending(), SIGINT);
}

TEST_F(StopSignalsTest, IgnoredSigint_IsRestoredToReachTheDescriptor) {
  ::signal(SIGINT, SIG_IGN);  // as a shell starts a background job
  auto signals = StopSignals::block_and_open();
  ASSERT_TRUE(signals);
  ASSERT_EQ(::raise(SIGINT), 0);
  EXPECT_EQ(signals->take_pending(), SIGINT);
}

}  // namespace
}  // namespace ldoem::driver
