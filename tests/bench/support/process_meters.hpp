// What the scaling benchmarks read about their own process: the measuring thread's CPU time, the
// resident set and the heap in use. Thread CPU time so that time spent descheduled on a shared
// machine does not count.
#pragma once

#include <malloc.h>
#include <time.h>
#include <unistd.h>

#include <fstream>

namespace ldoem::bench {

inline double thread_cpu_s() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Current (not peak) resident set, from /proc/self/statm, in MiB.
inline double current_rss_mib() {
  std::ifstream statm("/proc/self/statm");
  long total_pages = 0, resident_pages = 0;
  statm >> total_pages >> resident_pages;
  return static_cast<double>(resident_pages) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// Bytes the heap has handed out and not taken back: unlike RSS, this sees a scanner's objects
// even when they land in pages the scene's loading touched and freed before.
inline double heap_in_use_mib() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd) / (1024.0 * 1024.0);
}

}  // namespace ldoem::bench
