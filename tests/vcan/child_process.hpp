// Runs a helper program (cansend, candump, ip) for a test, with its stdout on a pipe the test
// can poll, and a hard limit so a stuck child never hangs the test (test_support::Child spawns
// and reaps).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/test_support/child.hpp"

namespace ldoem::test {

class CapturedProcess {
 public:
  // argv[0] from PATH, stdin /dev/null and stdout captured; stderr inherited.
  static std::optional<CapturedProcess> start(const std::vector<std::string>& argv);
  CapturedProcess(CapturedProcess&& other) noexcept;
  CapturedProcess& operator=(CapturedProcess&&) = delete;
  ~CapturedProcess();  // kills and reaps a child still running

  // Appends whatever stdout has to output(); waits at most `max_wait` for something to arrive.
  void collect_output(std::chrono::milliseconds max_wait);
  // Waits for exit (killing it after `limit`); the exit status, or nothing if it was killed.
  std::optional<int> wait(std::chrono::milliseconds limit);
  bool running();
  const std::string& output() const { return output_; }

 private:
  CapturedProcess(test_support::Child child, int stdout_fd) : child_(std::move(child)), stdout_fd_(stdout_fd) {}
  test_support::Child child_;
  int stdout_fd_ = -1;
  std::string output_;
};

// Runs argv to completion (limit 10 s) and returns its exit status (nothing if it was killed).
std::optional<int> run_program(const std::vector<std::string>& argv);

}  // namespace ldoem::test
