// Runs ldoem-emud as a child process for the integration tests (qtest style, design.md convention 4):
// stdout on a pipe (the endpoint lines and "ready"), stderr to a file the test can read, and a
// hard limit so that a stuck daemon never hangs the test (test_support::Child spawns and reaps).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/test_support/child.hpp"
#include "ldoem/test_support/temp_dir.hpp"

namespace ldoem::daemon::test {

class DaemonProcess {
 public:
  // Starts LDOEM_EMUD_PATH with `arguments`.
  static std::optional<DaemonProcess> start(const std::vector<std::string>& arguments);
  // Any program found on PATH (cansend, candump) with the same plumbing.
  static std::optional<DaemonProcess> start_program(const std::string& program,
                                                    const std::vector<std::string>& arguments);
  DaemonProcess(DaemonProcess&& other) noexcept;
  DaemonProcess& operator=(DaemonProcess&&) = delete;
  ~DaemonProcess();  // SIGKILL and reap a child still running

  // Reads stdout until a line "ready" (true) or until the child exits / `limit` passes (false).
  bool wait_ready(std::chrono::milliseconds limit = std::chrono::seconds(20));
  // "tcp 127.0.0.1:40123" -> endpoints()["tcp"] = "127.0.0.1:40123"
  const std::map<std::string, std::string>& endpoints() const { return endpoints_; }
  std::uint16_t tcp_port() const;

  void signal(int signal_number) { child_.signal(signal_number); }
  pid_t pid() const { return child_.pid(); }
  // Still running (not exited, not reaped).
  bool alive();
  // VmRSS from /proc/PID/status in KiB; nothing once the process is gone.
  std::optional<std::uint64_t> rss_kib() const;
  // Exit status (WEXITSTATUS, or 128 + signal when killed by one); nothing after `limit`.
  std::optional<int> wait(std::chrono::milliseconds limit = std::chrono::seconds(20));
  std::string stderr_text() const;
  const std::string& stdout_text() const { return stdout_; }

 private:
  DaemonProcess(test_support::Child child, int stdout_fd, std::string stderr_path)
      : child_(std::move(child)), stdout_fd_(stdout_fd), stderr_path_(std::move(stderr_path)) {}
  test_support::Child child_;
  int stdout_fd_ = -1;
  std::string stderr_path_;
  std::string stdout_;
  std::map<std::string, std::string> endpoints_;
};

// Scene files for a test go into a fresh temporary folder that is removed at the end.
using test_support::TempDir;

// The minimal scene (one wall 5 m ahead, D9 no effects), as text.
std::string minimal_scene_text();

}  // namespace ldoem::daemon::test
