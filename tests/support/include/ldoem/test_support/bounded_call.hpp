// Issue 27: tests of calls that used to hang (open() of a FIFO) or to grow without limit. A hang
// must fail the test, not stall ctest until its timeout: the call runs on a detached thread and
// the test stops waiting after `limit` (the thread is left blocked; the test process ends soon).
// Memory is judged by the growth of the process's peak RSS (getrusage), which needs no cgroup.
#pragma once

#include <sys/resource.h>

#include <chrono>
#include <future>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

namespace ldoem::test_support {

// f's result, or nothing when it did not return within `limit`. f must own what it uses (it may
// outlive the caller's frame).
template <class F>
auto call_within(std::chrono::milliseconds limit, F f) -> std::optional<decltype(f())> {
  using Result = decltype(f());
  auto promise = std::make_shared<std::promise<Result>>();
  std::future<Result> future = promise->get_future();
  std::thread([promise, f = std::move(f)]() mutable { promise->set_value(f()); }).detach();
  if (future.wait_for(limit) != std::future_status::ready) return std::nullopt;
  return future.get();
}

// The process's peak resident set so far, in bytes (ru_maxrss is in KiB on Linux).
inline std::size_t peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;
}

}  // namespace ldoem::test_support
