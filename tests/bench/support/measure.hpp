// Measuring helpers for the benchmark programs: peak resident memory, and interleaved timing
// (jobs run in turn, round after round, each keeps its fastest round, timed in this thread's CPU
// time), which keeps ratios honest on a loaded machine: time spent descheduled while other
// processes run is not counted, and a slow phase of the machine hits every job alike.
#pragma once

#include <functional>
#include <span>
#include <vector>

namespace ldoem::bench {

// getrusage(RUSAGE_SELF).ru_maxrss in MiB: the process's peak resident set so far.
[[nodiscard]] double peak_rss_mib();

// Thread CPU seconds of each job's fastest round.
[[nodiscard]] std::vector<double> fastest_interleaved(std::span<const std::function<void()>> jobs, int rounds);

}  // namespace ldoem::bench
