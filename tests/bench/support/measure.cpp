#include "measure.hpp"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ldoem::bench {
namespace {

double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

std::vector<double> fastest_interleaved(std::span<const std::function<void()>> jobs, int rounds) {
  std::vector<double> fastest(jobs.size(), std::numeric_limits<double>::infinity());
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      const double start_s = thread_cpu_seconds();
      jobs[j]();
      fastest[j] = std::min(fastest[j], thread_cpu_seconds() - start_s);
    }
  }
  return fastest;
}

std::vector<std::vector<double>> interleaved_rounds(std::span<const std::function<void()>> jobs, int rounds) {
  for (const auto& job : jobs) job();  // warm-up: caches, lazily built indices, page faults
  std::vector<std::vector<double>> times(jobs.size());
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      const double start_s = thread_cpu_seconds();
      jobs[j]();
      times[j].push_back(thread_cpu_seconds() - start_s);
    }
  }
  return times;
}

int rounds_for_budget(const std::function<void()>& a, const std::function<void()>& b, double budget_s,
                      int min_rounds, int max_rounds) {
  double one_round_s = 0.0;
  for (const auto* job : {&a, &b}) {
    const double start_s = thread_cpu_seconds();
    (*job)();
    one_round_s += thread_cpu_seconds() - start_s;
  }
  if (!(one_round_s > 0.0)) return max_rounds;
  const double rounds = std::ceil(budget_s / one_round_s);
  return static_cast<int>(std::clamp(rounds, static_cast<double>(min_rounds), static_cast<double>(max_rounds)));
}

Spread spread_of(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  // Linear interpolation between the closest ranks.
  const auto quantile = [&](double q) {
    const double position = q * static_cast<double>(values.size() - 1);
    const auto below = static_cast<std::size_t>(position);
    const std::size_t above = std::min(below + 1, values.size() - 1);
    const double fraction = position - static_cast<double>(below);
    return values[below] + fraction * (values[above] - values[below]);
  };
  return {quantile(0.5), quantile(0.25), quantile(0.75), values.front(), values.back()};
}

std::vector<double> round_ratios(std::span<const double> numerator, std::span<const double> denominator) {
  std::vector<double> ratios;
  for (std::size_t r = 0; r < std::min(numerator.size(), denominator.size()); ++r) {
    ratios.push_back(numerator[r] / denominator[r]);
  }
  return ratios;
}

}  // namespace ldoem::bench
