// One child process of a test (ldoem-emud, the hub, the scan tool, can-utils): started with
// posix_spawnp, stdin on /dev/null and stdout/stderr where the caller says, every wait bounded,
// and never left behind (the destructor kills and reaps it). The tests' launchers (the daemon
// tests' DaemonProcess, the e2e ChildProcess, the vcan ChildProcess) differ only in what they do
// with the output; the spawning and reaping are this.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace ldoem::test_support {

// Where the child's stdout or stderr goes: a descriptor of ours it gets as its own (a pipe's
// write end), a file created or truncated, or, with neither, ours (inherited).
struct ChildStream {
  int fd = -1;
  std::string path;
};

struct ChildSetup {
  ChildStream out;
  ChildStream err;
  std::vector<std::string> environment;  // NAME=VALUE entries added to the test's environment
};

// WEXITSTATUS, or 128 + N after signal N (as a shell reports it).
int exit_status_of(int wait_status);

class Child {
 public:
  // argv[0] is looked up on PATH unless it holds a slash. The child starts with no signal
  // blocked, whatever the test runner blocks. Nothing when the program cannot be started.
  static std::optional<Child> spawn(const std::vector<std::string>& argv, const ChildSetup& setup = {});
  Child(Child&& other) noexcept;
  Child& operator=(Child&&) = delete;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child();  // SIGKILL and reap a child still running

  // Reaps it if it has exited, without waiting; true once it has.
  bool exited();
  // The exit status; nothing when `limit` passes first (the child runs on). A zero limit asks
  // "has it exited?".
  std::optional<int> wait(std::chrono::milliseconds limit);
  // SIGTERM, then SIGKILL after `grace`; the exit status.
  int stop(std::chrono::milliseconds grace);
  // SIGKILL now and reap.
  void kill_now();
  void signal(int signal_number);
  pid_t pid() const { return pid_; }

 private:
  explicit Child(pid_t pid) : pid_(pid) {}
  pid_t pid_ = -1;
  std::optional<int> exit_status_;
};

}  // namespace ldoem::test_support
