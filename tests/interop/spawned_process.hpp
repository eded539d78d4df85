// A program the interop test runs beside itself (ldoem-emud, isotpdump): stdout and stderr go to
// files, as a shell's `prog > out 2> err &` would, so the test reads what it printed at any time
// and a child that fills a pipe can never stall. The destructor kills and reaps a child still
// running, so a failed assertion leaves nothing behind.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace ldoem::interop {

class SpawnedProcess {
 public:
  // posix_spawnp(argv) with stdin /dev/null; nothing when the program cannot be started.
  static std::optional<SpawnedProcess> start(const std::vector<std::string>& argv,
                                             const std::string& stdout_path,
                                             const std::string& stderr_path);
  SpawnedProcess(SpawnedProcess&& other) noexcept;
  SpawnedProcess& operator=(SpawnedProcess&&) = delete;
  SpawnedProcess(const SpawnedProcess&) = delete;
  SpawnedProcess& operator=(const SpawnedProcess&) = delete;
  ~SpawnedProcess();

  void signal(int signal_number) const;
  // Exit status, or 128 + N when signal N ended it; nothing if it still runs after `limit`.
  std::optional<int> wait(std::chrono::milliseconds limit);

 private:
  explicit SpawnedProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_ = -1;
};

// The whole file, or "" when it cannot be read.
std::string read_text_file(const std::string& path);

// Polls `path` every 10 ms until its text satisfies `done` or `limit` passes; the last text read.
template <class Predicate>
std::string wait_for_file_text(const std::string& path, std::chrono::milliseconds limit, Predicate done) {
  const auto end = std::chrono::steady_clock::now() + limit;
  std::string text = read_text_file(path);
  while (!done(text) && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    text = read_text_file(path);
  }
  return text;
}

}  // namespace ldoem::interop
