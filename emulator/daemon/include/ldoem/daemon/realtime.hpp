// ldoem-emud --realtime: ask the kernel to run the daemon before ordinary work (SCHED_FIFO) and
// to keep its memory resident (mlockall), so that a busy machine delays its revolutions less
// (docs/latency.md). Neither is required: what was refused is said in one line, and the daemon
// runs on at normal priority (issue 23).
#pragma once

#include <string>

namespace ldoem::daemon {

// The priority asked for: above ordinary tasks and most user threads, below the kernel's
// interrupt threads (50) and the usual audio servers, so a stuck daemon cannot lock them out.
inline constexpr int kRealtimePriority = 10;

struct RealtimeResult {
  bool scheduled = false;  // SCHED_FIFO granted
  bool locked = false;     // mlockall(MCL_CURRENT | MCL_FUTURE) granted
  std::string message;     // one line for stderr, what was granted and what not and why
};

// Applies both to the calling process (threads created later inherit the policy; a forked
// child does not: SCHED_RESET_ON_FORK). Memory is locked for the future only when the lock
// limit cannot make a later allocation fail (RLIMIT_MEMLOCK unlimited, or root).
RealtimeResult request_realtime();

}  // namespace ldoem::daemon
