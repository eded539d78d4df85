// One epoll loop per daemon (design.md): endpoints register their descriptors with a callback,
// timers fire on the monotonic clock, SIGINT/SIGTERM arrive through a signalfd. No threads.
// This is the one place of the emulator that reads a clock; it only drives the simulated clock
// (D7), the pure state machines get time as a parameter.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "ldoem/io/io_error.hpp"
#include "ldoem/base/unique_fd.hpp"

namespace ldoem::io {

using MonotonicClock = std::chrono::steady_clock;  // CLOCK_MONOTONIC on Linux
using MonotonicTime = MonotonicClock::time_point;

// What a watched descriptor should report (bit set; combine with |).
enum class Interest : std::uint32_t { readable = 1, writable = 2 };
constexpr Interest operator|(Interest a, Interest b) {
  return static_cast<Interest>(static_cast<std::uint32_t>(a) | static_cast<std::uint32_t>(b));
}
constexpr bool has(Interest set, Interest flag) {
  return (static_cast<std::uint32_t>(set) & static_cast<std::uint32_t>(flag)) != 0;
}

// Order of the callbacks of descriptors that are ready in the same round: kFirstInRound before
// kInRoundOrder. For an input that must count before any telegram read in the same round (D8:
// the tilt stepper's register writes, which a host makes before asking for the next profile).
enum class RoundOrder : std::uint8_t { first, normal };
inline constexpr RoundOrder kFirstInRound = RoundOrder::first;
inline constexpr RoundOrder kInRoundOrder = RoundOrder::normal;

// What the kernel reported for a descriptor in one round.
struct Readiness {
  bool readable = false;
  bool writable = false;
  bool hang_up = false;  // EPOLLHUP/EPOLLRDHUP: the peer closed
  bool error = false;    // EPOLLERR: read or write will report the error
};

class EventLoop {
 public:
  using FdCallback = std::function<void(Readiness)>;
  using TimerCallback = std::function<void()>;
  using SignalCallback = std::function<void(int signal_number)>;
  using TimerId = std::uint64_t;

  // The loop registers callbacks that point back at it, so it lives at a fixed address.
  static IoResult<std::unique_ptr<EventLoop>> create();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;
  ~EventLoop();

  // Level-triggered: the callback runs each round while the condition holds. A callback may
  // watch, unwatch (itself too), add or cancel timers, and stop the loop.
  IoStatus watch(int fd, Interest interest, FdCallback callback, RoundOrder order = kInRoundOrder);
  IoStatus change_interest(int fd, Interest interest);
  void unwatch(int fd);  // no-op for a descriptor that is not watched
  bool is_watched(int fd) const;

  // Timers fire once, in deadline order (equal deadlines: in the order they were added).
  TimerId add_timer_at(MonotonicTime deadline, TimerCallback callback);
  TimerId add_timer_after(std::chrono::nanoseconds delay, TimerCallback callback);
  bool cancel_timer(TimerId id);  // false when it already fired or never existed
  std::size_t pending_timers() const { return timers_.size(); }

  // Blocks the signals for this thread and delivers them through a signalfd as loop events.
  // pthread_sigmask acts on the calling thread only: a thread started earlier keeps the old
  // mask and may take the signal itself (its default action kills the process). Callers that
  // start threads (Embree/TBB workers, std::thread) must block these signals before doing so,
  // so that every later thread inherits the mask; ldoem-emud does it first thing in
  // Daemon::create.
  IoStatus on_signals(const std::vector<int>& signal_numbers, SignalCallback callback);
  // SIGINT and SIGTERM stop the loop; stop_signal() then tells which one (exit 128 + it).
  IoStatus stop_on_termination_signals();
  std::optional<int> stop_signal() const { return stop_signal_; }

  // Runs until stop(). Fails only when epoll itself fails.
  IoStatus run();
  // Runs until stop() or until `duration` has passed, whichever comes first.
  IoStatus run_for(std::chrono::nanoseconds duration);
  // One round: waits at most `max_wait` (or until the next timer) and dispatches what is ready.
  IoStatus run_once(std::chrono::nanoseconds max_wait);
  void stop() { stop_requested_ = true; }
  bool stop_requested() const { return stop_requested_; }

  static MonotonicTime now() { return MonotonicClock::now(); }

 private:
  EventLoop() = default;
  struct Watch {
    std::uint64_t generation;
    std::shared_ptr<FdCallback> callback;
    RoundOrder order = kInRoundOrder;
  };
  IoStatus dispatch_ready(int timeout_ms);
  void fire_due_timers();
  int wait_budget_ms(MonotonicTime limit) const;
  void handle_signalfd();

  base::UniqueFd epoll_fd_;
  base::UniqueFd signal_fd_;
  SignalCallback signal_callback_;
  std::unordered_map<int, Watch> watches_;
  std::uint64_t next_generation_ = 1;
  // (deadline, id) orders timers by deadline, ties by creation order.
  std::map<std::pair<MonotonicTime, TimerId>, TimerCallback> timers_;
  std::unordered_map<TimerId, MonotonicTime> timer_deadlines_;
  TimerId next_timer_id_ = 1;
  bool stop_requested_ = false;
  std::optional<int> stop_signal_;
};

}  // namespace ldoem::io
