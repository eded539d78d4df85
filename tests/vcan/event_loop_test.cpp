#include "ldoem/io/event_loop.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {
namespace {

using namespace std::chrono_literals;

std::unique_ptr<EventLoop> make_loop() {
  auto loop = EventLoop::create();
  EXPECT_TRUE(loop) << loop.error().message();
  return loop ? std::move(*loop) : nullptr;
}

struct Pipe {
  base::UniqueFd read_end;
  base::UniqueFd write_end;
};

Pipe make_pipe() {
  int fds[2] = {-1, -1};
  EXPECT_EQ(::pipe2(fds, O_CLOEXEC | O_NONBLOCK), 0);
  return Pipe{base::UniqueFd(fds[0]), base::UniqueFd(fds[1])};
}

TEST(EventLoop, Timers_FireInDeadlineOrderNotCreationOrder) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  std::string order;
  // Deadlines already past: one round fires all three, so no scheduling delay can matter.
  const auto base = EventLoop::now();
  loop->add_timer_at(base - 1ms, [&] { order += 'c'; });
  loop->add_timer_at(base - 3ms, [&] { order += 'a'; });
  loop->add_timer_at(base - 2ms, [&] { order += 'b'; });
  loop->add_timer_at(base + 1h, [&] { order += 'z'; });
  ASSERT_TRUE(loop->run_once(0ms));
  EXPECT_EQ(order, "abc");
  EXPECT_EQ(loop->pending_timers(), 1u);
}

TEST(EventLoop, TimersWithEqualDeadlines_FireInCreationOrder) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  std::string order;
  const auto deadline = EventLoop::now();
  for (char name : std::string("xyz")) {
    loop->add_timer_at(deadline, [&order, name] { order += name; });
  }
  ASSERT_TRUE(loop->run_once(0ms));
  EXPECT_EQ(order, "xyz");
}

TEST(EventLoop, CancelledTimer_NeverFires) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  bool fired = false;
  const auto id = loop->add_timer_after(1ms, [&] { fired = true; });
  EXPECT_TRUE(loop->cancel_timer(id));
  EXPECT_FALSE(loop->cancel_timer(id));
  ASSERT_TRUE(loop->run_for(20ms));
  EXPECT_FALSE(fired);
}

TEST(EventLoop, TimerCancellingALaterDueTimer_InTheSameRound_PreventsIt) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  const auto deadline = EventLoop::now();
  bool second_fired = false;
  EventLoop::TimerId second = 0;
  loop->add_timer_at(deadline, [&] { loop->cancel_timer(second); });
  second = loop->add_timer_at(deadline, [&] { second_fired = true; });
  ASSERT_TRUE(loop->run_once(0ms));
  EXPECT_FALSE(second_fired);
}

TEST(EventLoop, ReadableDescriptor_RunsItsCallbackWithTheData) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  Pipe pipe = make_pipe();
  std::string received;
  ASSERT_TRUE(loop->watch(pipe.read_end.get(), Interest::readable, [&](Readiness readiness) {
    EXPECT_TRUE(readiness.readable);
    char buffer[16];
    const ssize_t got = ::read(pipe.read_end.get(), buffer, sizeof buffer);
    ASSERT_GT(got, 0);
    received.append(buffer, static_cast<std::size_t>(got));
    loop->stop();
  }));
  ASSERT_EQ(::write(pipe.write_end.get(), "hi", 2), 2);
  ASSERT_TRUE(loop->run_for(2s));
  EXPECT_EQ(received, "hi");
}

TEST(EventLoop, CallbackUnwatchingItself_IsNotCalledAgain) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  Pipe pipe = make_pipe();
  int calls = 0;
  ASSERT_TRUE(loop->watch(pipe.read_end.get(), Interest::readable, [&](Readiness) {
    ++calls;
    loop->unwatch(pipe.read_end.get());
  }));
  ASSERT_EQ(::write(pipe.write_end.get(), "x", 1), 1);  // stays readable: level-triggered
  ASSERT_TRUE(loop->run_for(30ms));
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(loop->is_watched(pipe.read_end.get()));
}

TEST(EventLoop, ClosedWriteEnd_IsReportedAsHangUp) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  Pipe pipe = make_pipe();
  bool hang_up = false;
  ASSERT_TRUE(loop->watch(pipe.read_end.get(), Interest::readable, [&](Readiness readiness) {
    hang_up = readiness.hang_up;
    loop->stop();
  }));
  pipe.write_end.reset();
  ASSERT_TRUE(loop->run_for(2s));
  EXPECT_TRUE(hang_up);
}

TEST(EventLoop, WatchingAnInvalidDescriptor_IsAnErrorNamingIt) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  auto watched = loop->watch(-1, Interest::readable, [](Readiness) {});
  ASSERT_FALSE(watched);
  EXPECT_EQ(watched.error().error_number, EBADF);
  EXPECT_EQ(watched.error().message(), "epoll_ctl add fd -1: Bad file descriptor");
}

TEST(EventLoop, Sigterm_StopsTheLoopAndIsReported) {
  sigset_t before;
  ASSERT_EQ(::pthread_sigmask(SIG_SETMASK, nullptr, &before), 0);
  {
    auto loop = make_loop();
    ASSERT_TRUE(loop);
    ASSERT_TRUE(loop->stop_on_termination_signals());
    loop->add_timer_after(1ms, [] { ::raise(SIGTERM); });
    ASSERT_TRUE(loop->run_for(5s));
    ASSERT_TRUE(loop->stop_signal().has_value());
    EXPECT_EQ(*loop->stop_signal(), SIGTERM);
  }
  ASSERT_EQ(::pthread_sigmask(SIG_SETMASK, &before, nullptr), 0);
}

TEST(EventLoop, RunFor_ReturnsWhenTheTimeIsUp) {
  auto loop = make_loop();
  ASSERT_TRUE(loop);
  bool late_timer_fired = false;
  loop->add_timer_after(10s, [&] { late_timer_fired = true; });
  ASSERT_TRUE(loop->run_for(10ms));
  EXPECT_FALSE(late_timer_fired);
  EXPECT_FALSE(loop->stop_requested());
}

}  // namespace
}  // namespace ldoem::io
