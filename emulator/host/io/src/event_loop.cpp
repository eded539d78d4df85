#include "ldoem/io/event_loop.hpp"

#include <sys/epoll.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <string>

namespace ldoem::io {
namespace {

std::uint32_t epoll_events_for(Interest interest) {
  std::uint32_t events = EPOLLRDHUP;
  if (has(interest, Interest::readable)) {
    events |= EPOLLIN;
  }
  if (has(interest, Interest::writable)) {
    events |= EPOLLOUT;
  }
  return events;
}

Readiness readiness_from(std::uint32_t events) {
  Readiness readiness;
  readiness.readable = (events & (EPOLLIN | EPOLLPRI)) != 0;
  readiness.writable = (events & EPOLLOUT) != 0;
  readiness.hang_up = (events & (EPOLLHUP | EPOLLRDHUP)) != 0;
  readiness.error = (events & EPOLLERR) != 0;
  return readiness;
}

std::string fd_name(int fd) { return "fd " + std::to_string(fd); }

}  // namespace

IoResult<std::unique_ptr<EventLoop>> EventLoop::create() {
  std::unique_ptr<EventLoop> loop(new EventLoop());
  loop->epoll_fd_.reset(::epoll_create1(EPOLL_CLOEXEC));
  if (!loop->epoll_fd_.valid()) {
    return io_failure(last_system_error("epoll_create1"));
  }
  return loop;
}

EventLoop::~EventLoop() = default;

IoStatus EventLoop::watch(int fd, Interest interest, FdCallback callback, RoundOrder order) {
  epoll_event event{};
  event.events = epoll_events_for(interest);
  event.data.fd = fd;
  if (::epoll_ctl(epoll_fd_.get(), EPOLL_CTL_ADD, fd, &event) != 0) {
    return io_failure(last_system_error("epoll_ctl add", fd_name(fd)));
  }
  watches_[fd] = Watch{next_generation_++, std::make_shared<FdCallback>(std::move(callback)), order};
  return Done{};
}

IoStatus EventLoop::change_interest(int fd, Interest interest) {
  epoll_event event{};
  event.events = epoll_events_for(interest);
  event.data.fd = fd;
  if (::epoll_ctl(epoll_fd_.get(), EPOLL_CTL_MOD, fd, &event) != 0) {
    return io_failure(last_system_error("epoll_ctl mod", fd_name(fd)));
  }
  return Done{};
}

void EventLoop::unwatch(int fd) {
  if (watches_.erase(fd) == 0) {
    return;
  }
  // ENOENT/EBADF here mean the descriptor was closed first, which already removed it from epoll.
  (void)::epoll_ctl(epoll_fd_.get(), EPOLL_CTL_DEL, fd, nullptr);
}

bool EventLoop::is_watched(int fd) const { return watches_.contains(fd); }

EventLoop::TimerId EventLoop::add_timer_at(MonotonicTime deadline, TimerCallback callback) {
  const TimerId id = next_timer_id_++;
  timers_.emplace(std::make_pair(deadline, id), std::move(callback));
  timer_deadlines_.emplace(id, deadline);
  return id;
}

EventLoop::TimerId EventLoop::add_timer_after(std::chrono::nanoseconds delay,
                                              TimerCallback callback) {
  return add_timer_at(now() + delay, std::move(callback));
}

bool EventLoop::cancel_timer(TimerId id) {
  const auto found = timer_deadlines_.find(id);
  if (found == timer_deadlines_.end()) {
    return false;
  }
  timers_.erase(std::make_pair(found->second, id));
  timer_deadlines_.erase(found);
  return true;
}

IoStatus EventLoop::on_signals(const std::vector<int>& signal_numbers, SignalCallback callback) {
  sigset_t mask;
  sigemptyset(&mask);
  for (const int signal_number : signal_numbers) {
    if (sigaddset(&mask, signal_number) != 0) {
      return io_failure(last_system_error("sigaddset", std::to_string(signal_number)));
    }
  }
  // Blocked signals stay pending for the signalfd instead of running a handler.
  if (const int error = ::pthread_sigmask(SIG_BLOCK, &mask, nullptr); error != 0) {
    return io_failure(IoError{"pthread_sigmask", {}, error, {}});
  }
  const int existing = signal_fd_.valid() ? signal_fd_.get() : -1;
  const int fd = ::signalfd(existing, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
  if (fd < 0) {
    return io_failure(last_system_error("signalfd"));
  }
  signal_callback_ = std::move(callback);
  if (existing >= 0) {
    return Done{};
  }
  signal_fd_.reset(fd);
  return watch(fd, Interest::readable, [this](Readiness) { handle_signalfd(); });
}

IoStatus EventLoop::stop_on_termination_signals() {
  return on_signals({SIGINT, SIGTERM}, [this](int signal_number) {
    stop_signal_ = signal_number;
    stop();
  });
}

void EventLoop::handle_signalfd() {
  signalfd_siginfo info{};
  while (::read(signal_fd_.get(), &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
    if (signal_callback_) {
      signal_callback_(static_cast<int>(info.ssi_signo));
    }
  }
}

int EventLoop::wait_budget_ms(MonotonicTime limit) const {
  MonotonicTime wake = limit;
  if (!timers_.empty()) {
    wake = std::min(wake, timers_.begin()->first.first);
  }
  const auto remaining = wake - now();
  if (remaining <= std::chrono::nanoseconds::zero()) {
    return 0;
  }
  // Round up: waking a little late is fine, waking early would spin until the deadline.
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(remaining).count();
  return static_cast<int>(std::min<std::int64_t>(ms, 60'000));
}

IoStatus EventLoop::dispatch_ready(int timeout_ms) {
  std::array<epoll_event, 64> events{};
  const int count = ::epoll_wait(epoll_fd_.get(), events.data(), static_cast<int>(events.size()),
                                 timeout_ms);
  if (count < 0) {
    if (errno == EINTR) {
      return Done{};
    }
    return io_failure(last_system_error("epoll_wait"));
  }
  // Callbacks may unwatch descriptors (and the number may be reused by a new watch in the same
  // round): snapshot the generation so a stale event never reaches the wrong callback.
  struct ReadyWatch {
    int fd;
    Watch watch_entry;
    std::uint32_t event_bits;
  };
  std::vector<ReadyWatch> ready;
  ready.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const epoll_event& event = events[static_cast<std::size_t>(i)];
    const auto found = watches_.find(event.data.fd);
    if (found != watches_.end()) {
      ready.push_back(ReadyWatch{event.data.fd, found->second, event.events});
    }
  }
  std::stable_partition(ready.begin(), ready.end(),
                        [](const ReadyWatch& entry) { return entry.watch_entry.order == kFirstInRound; });
  for (const ReadyWatch& entry : ready) {
    const auto found = watches_.find(entry.fd);
    if (found != watches_.end() && found->second.generation == entry.watch_entry.generation) {
      (*entry.watch_entry.callback)(readiness_from(entry.event_bits));
    }
  }
  return Done{};
}

void EventLoop::fire_due_timers() {
  const MonotonicTime current = now();
  // Only timers due at entry fire in this round, so a timer re-arming itself for "now" cannot
  // starve the descriptors.
  std::vector<TimerId> due;
  for (const auto& [key, callback] : timers_) {
    if (key.first > current) {
      break;
    }
    due.push_back(key.second);
  }
  for (const TimerId id : due) {
    const auto found = timer_deadlines_.find(id);
    if (found == timer_deadlines_.end()) {
      continue;  // cancelled by an earlier callback of this round
    }
    auto node = timers_.extract(std::make_pair(found->second, id));
    timer_deadlines_.erase(found);
    node.mapped()();
  }
}

IoStatus EventLoop::run_once(std::chrono::nanoseconds max_wait) {
  const int timeout_ms = wait_budget_ms(now() + max_wait);
  if (IoStatus status = dispatch_ready(timeout_ms); !status) {
    return status;
  }
  fire_due_timers();
  return Done{};
}

IoStatus EventLoop::run() {
  stop_requested_ = false;
  while (!stop_requested_) {
    if (IoStatus status = run_once(std::chrono::seconds(60)); !status) {
      return status;
    }
  }
  return Done{};
}

IoStatus EventLoop::run_for(std::chrono::nanoseconds duration) {
  stop_requested_ = false;
  const MonotonicTime end = now() + duration;
  while (!stop_requested_) {
    const auto remaining = end - now();
    if (remaining <= std::chrono::nanoseconds::zero()) {
      break;
    }
    if (IoStatus status = run_once(remaining); !status) {
      return status;
    }
  }
  return Done{};
}

}  // namespace ldoem::io
