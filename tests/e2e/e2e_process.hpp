// Child processes for the end-to-end tests: ldoem-emud, ldoem-hub and ldoem-scan (or any
// program) with stdout and stderr captured in files, a wall-clock limit on every wait, and a
// destructor that never leaves a child behind (SIGTERM, then SIGKILL; test_support::Child).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/test_support/child.hpp"
#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::e2e {

using test_support::read_file;
using test_support::TempDir;

class ChildProcess {
 public:
  // Starts `program` with `arguments`; stdout and stderr go to `<log_prefix>.out` and `.err`.
  // `environment` entries (NAME=VALUE) are added to the caller's environment.
  static std::optional<ChildProcess> start(const std::string& program, const std::vector<std::string>& arguments,
                                           const std::string& log_prefix,
                                           const std::vector<std::string>& environment = {});
  ChildProcess(ChildProcess&& other) noexcept = default;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess();

  // Exit status (WEXITSTATUS, or 128 + N after signal N); nothing when `limit` passes first.
  std::optional<int> wait(std::chrono::milliseconds limit) { return child_.wait(limit); }
  // SIGTERM, then SIGKILL after `grace`; returns the exit status.
  int stop(std::chrono::milliseconds grace = std::chrono::seconds(5)) { return child_.stop(grace); }
  // Polls stdout (or stderr) until a line contains `text`; false when the child exits first or
  // `limit` passes.
  bool wait_for_line(const std::string& text, bool in_stderr, std::chrono::milliseconds limit);

  std::string stdout_text() const;
  std::string stderr_text() const;
  pid_t pid() const { return child_.pid(); }

 private:
  ChildProcess(test_support::Child child, std::string log_prefix)
      : child_(std::move(child)), log_prefix_(std::move(log_prefix)) {}

  test_support::Child child_;
  std::string log_prefix_;
};

}  // namespace ldoem::e2e
