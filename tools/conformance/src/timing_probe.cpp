#include "timing_probe.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>

namespace ldoem::conformance {
namespace {

std::int64_t monotonic_ns() {
  timespec now{};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  return std::int64_t{now.tv_sec} * 1'000'000'000 + now.tv_nsec;
}

std::string probe_ms(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", value);
  return text;
}

double nearest_rank(const std::vector<double>& sorted, double fraction) {
  if (sorted.empty()) return 0;
  const auto rank = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

constexpr std::int64_t kTickNs = 1'000'000;  // 1 ms

}  // namespace

ProbeSummary summarize(std::vector<double>& lateness_ms, double run_delay, double window_ms) {
  ProbeSummary summary;
  std::sort(lateness_ms.begin(), lateness_ms.end());
  summary.wakeups = lateness_ms.size();
  summary.p50_ms = nearest_rank(lateness_ms, 0.50);
  summary.p99_ms = nearest_rank(lateness_ms, 0.99);
  summary.max_ms = lateness_ms.empty() ? 0 : lateness_ms.back();
  summary.run_delay_ms = run_delay;
  summary.window_ms = window_ms;
  return summary;
}

std::optional<std::string> machine_busy(const ProbeSummary& probe, double tolerance_ms) {
  const bool stall = probe.max_ms >= tolerance_ms / 2;
  const bool common = probe.p99_ms >= tolerance_ms / 10;
  const bool starved = probe.window_ms > 0 && probe.run_delay_ms >= probe.window_ms / 10;
  if (!stall && !common && !starved) return std::nullopt;
  const double share = probe.window_ms > 0 ? 100.0 * probe.run_delay_ms / probe.window_ms : 0;
  return "machine busy: p99 wake-up " + probe_ms(probe.p99_ms) + " ms, max " + probe_ms(probe.max_ms) + " ms, run delay " +
         probe_ms(probe.run_delay_ms) + " ms (" + probe_ms(share) + " % of " + probe_ms(probe.window_ms) + " ms); tolerance " +
         probe_ms(tolerance_ms) + " ms";
}

std::string summary_line(int passed, int failed, int inconclusive) {
  return std::to_string(passed) + " passed, " + std::to_string(failed) + " failed, " + std::to_string(inconclusive) +
         " inconclusive";
}

double run_delay_ms() {
  // Fields: time on the CPU, time runnable waiting for it, timeslices (all ns, per thread: this
  // file is the thread-group leader's, the suite's main thread).
  std::ifstream file("/proc/self/schedstat");
  unsigned long long on_cpu = 0;
  unsigned long long waited = 0;
  if (!(file >> on_cpu >> waited)) return 0;
  return static_cast<double>(waited) / 1e6;
}

SchedulingProbe::SchedulingProbe() {
  lateness_ms_.reserve(4096);
  run_delay_start_ms_ = run_delay_ms();
  started_ns_ = monotonic_ns();
  thread_ = std::thread([this] { run(); });
}

SchedulingProbe::~SchedulingProbe() { stop(); }

void SchedulingProbe::run() {
  const int fd = ::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
  if (fd < 0) return;  // no probe: the window shows 0 wake-ups and judges nothing as busy
  std::int64_t target = monotonic_ns() + kTickNs;
  while (!stop_.load(std::memory_order_relaxed)) {
    itimerspec when{};
    when.it_value.tv_sec = static_cast<time_t>(target / 1'000'000'000);
    when.it_value.tv_nsec = static_cast<long>(target % 1'000'000'000);
    if (::timerfd_settime(fd, TFD_TIMER_ABSTIME, &when, nullptr) != 0) break;
    std::uint64_t expirations = 0;
    if (::read(fd, &expirations, sizeof expirations) != static_cast<ssize_t>(sizeof expirations)) continue;
    const std::int64_t now = monotonic_ns();
    const double late_ms = static_cast<double>(now - target) / 1e6;
    if (lateness_ms_.size() < kMaxSamples) {
      lateness_ms_.push_back(late_ms);
    } else {
      overflow_max_ms_ = std::max(overflow_max_ms_, late_ms);
    }
    // The next tick 1 ms after this wake-up: a stall counts once, not once per missed tick.
    target = now + kTickNs;
  }
  ::close(fd);
}

ProbeSummary SchedulingProbe::stop() {
  if (summary_) return *summary_;
  stop_.store(true, std::memory_order_relaxed);
  if (thread_.joinable()) thread_.join();
  const double window_ms = static_cast<double>(monotonic_ns() - started_ns_) / 1e6;
  summary_ = summarize(lateness_ms_, run_delay_ms() - run_delay_start_ms_, window_ms);
  summary_->max_ms = std::max(summary_->max_ms, overflow_max_ms_);
  return *summary_;
}

}  // namespace ldoem::conformance
