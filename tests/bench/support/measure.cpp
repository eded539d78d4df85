#include "measure.hpp"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
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

}  // namespace ldoem::bench
