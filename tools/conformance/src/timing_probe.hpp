// Whether the host could keep time while a case judged the wall clock. A case that measures
// arrivals against the host's clock (cadence, spin-up) cannot tell a slow device from a starved
// host; a probe running in the same window can: a thread sleeping on a 1 ms timerfd records how
// late each wake-up comes, and /proc/self/schedstat says how long the suite's main thread sat
// runnable without a CPU. If the probe saw the machine lose more time than the case's tolerance
// allows, a wall-clock failure is reported INCONCLUSIVE instead of FAIL (docs/conformance.md).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace ldoem::conformance {

struct ProbeSummary {
  std::size_t wakeups = 0;
  double p50_ms = 0;  // wake-up lateness behind the 1 ms timer
  double p99_ms = 0;
  double max_ms = 0;
  double run_delay_ms = 0;  // the main thread's time runnable but not running (schedstat)
  double window_ms = 0;     // how long the probe ran
};

// Percentiles of `lateness_ms` (nearest rank; the vector is reordered).
ProbeSummary summarize(std::vector<double>& lateness_ms, double run_delay_ms, double window_ms);

// Pure verdict: nullopt when the machine kept time well enough to judge a wall-clock quantity
// whose tolerance is `tolerance_ms`, else why not ("machine busy: p99 wake-up 37.0 ms, ...").
// Busy when one stall alone took half the tolerance (max), when stalls of a tenth of it were
// common (p99: a case waits on dozens of events, and each can be hit), or when the main thread
// waited for a CPU a tenth of the window (run delay).
std::optional<std::string> machine_busy(const ProbeSummary& probe, double tolerance_ms);

// The runner's summary line: "N passed, M failed, K inconclusive" (CI reads its first part).
std::string summary_line(int passed, int failed, int inconclusive);

// The probe thread; bounded: at most kMaxSamples wake-ups are kept (the max is kept beyond).
class SchedulingProbe {
 public:
  static constexpr std::size_t kMaxSamples = std::size_t{1} << 18;  // 4.4 min of 1 ms ticks
  SchedulingProbe();
  ~SchedulingProbe();
  SchedulingProbe(const SchedulingProbe&) = delete;
  SchedulingProbe& operator=(const SchedulingProbe&) = delete;
  // Stops the thread (within one tick) and summarizes the window.
  ProbeSummary stop();

 private:
  void run();
  std::atomic<bool> stop_{false};
  std::vector<double> lateness_ms_;
  double overflow_max_ms_ = 0;
  double run_delay_start_ms_ = 0;
  std::int64_t started_ns_ = 0;
  std::thread thread_;
  std::optional<ProbeSummary> summary_;
};

// The calling process's main-thread run delay in ms (/proc/self/schedstat, field 2), 0 if unknown.
double run_delay_ms();

}  // namespace ldoem::conformance
