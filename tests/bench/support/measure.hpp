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

// Thread CPU seconds of every round of each job ([job][round]), the jobs run in turn round after
// round, after one warm-up round that is not kept. A ratio taken round by round compares two
// jobs that ran back to back, in the same phase of a shared machine.
[[nodiscard]] std::vector<std::vector<double>> interleaved_rounds(std::span<const std::function<void()>> jobs,
                                                                  int rounds);

// How many interleaved rounds of a and b fill about `budget_s` of CPU time, judged from one round
// of each; at least `min_rounds`, at most `max_rounds`.
[[nodiscard]] int rounds_for_budget(const std::function<void()>& a, const std::function<void()>& b, double budget_s,
                                    int min_rounds, int max_rounds);

// The median of some values and how far they spread: quartiles and extremes.
struct Spread {
  double median = 0.0;
  double lower_quartile = 0.0;
  double upper_quartile = 0.0;
  double min = 0.0;
  double max = 0.0;
};
[[nodiscard]] Spread spread_of(std::vector<double> values);

// numerator[r] / denominator[r] for every round r.
[[nodiscard]] std::vector<double> round_ratios(std::span<const double> numerator, std::span<const double> denominator);

}  // namespace ldoem::bench
