#include "daemon_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <utility>

namespace ldoem::daemon::test {

std::optional<DaemonProcess> DaemonProcess::start(const std::vector<std::string>& arguments) {
  return start_program(LDOEM_EMUD_PATH, arguments);
}

std::optional<DaemonProcess> DaemonProcess::start_program(const std::string& program,
                                                          const std::vector<std::string>& arguments) {
  char stderr_template[] = "/tmp/ldoem-emud-stderr-XXXXXX";
  const int stderr_fd = ::mkstemp(stderr_template);
  if (stderr_fd < 0) return std::nullopt;
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return std::nullopt;
  std::vector<std::string> argv_text{program};
  argv_text.insert(argv_text.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& text : argv_text) argv.push_back(text.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return std::nullopt;
  if (pid == 0) {
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    ::dup2(stderr_fd, STDERR_FILENO);
    const int null_fd = ::open("/dev/null", O_RDONLY);
    ::dup2(null_fd, STDIN_FILENO);
    // The test runner may block signals (gtest does not, but be sure): the daemon wants defaults.
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  ::close(stderr_fd);
  return DaemonProcess(pid, pipe_fds[0], stderr_template);
}

DaemonProcess::DaemonProcess(DaemonProcess&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)),
      stdout_fd_(std::exchange(other.stdout_fd_, -1)),
      stderr_path_(std::move(other.stderr_path_)),
      stdout_(std::move(other.stdout_)),
      endpoints_(std::move(other.endpoints_)),
      exit_status_(other.exit_status_) {}

DaemonProcess::~DaemonProcess() {
  if (pid_ > 0 && !exit_status_) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  if (stdout_fd_ >= 0) ::close(stdout_fd_);
  if (!stderr_path_.empty()) ::unlink(stderr_path_.c_str());
}

bool DaemonProcess::wait_ready(std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  std::size_t parsed = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd descriptor{stdout_fd_, POLLIN, 0};
    if (::poll(&descriptor, 1, 50) > 0) {
      char buffer[4096];
      const ssize_t count = ::read(stdout_fd_, buffer, sizeof buffer);
      if (count <= 0) return false;  // the daemon exited before it was ready
      stdout_.append(buffer, static_cast<std::size_t>(count));
    }
    std::size_t end;
    while ((end = stdout_.find('\n', parsed)) != std::string::npos) {
      const std::string line = stdout_.substr(parsed, end - parsed);
      parsed = end + 1;
      if (line == "ready") return true;
      const auto space = line.find(' ');
      if (space != std::string::npos) endpoints_[line.substr(0, space)] = line.substr(space + 1);
    }
  }
  return false;
}

std::uint16_t DaemonProcess::tcp_port() const {
  const auto tcp = endpoints_.find("tcp");
  if (tcp == endpoints_.end()) return 0;
  return static_cast<std::uint16_t>(std::stoul(tcp->second.substr(tcp->second.rfind(':') + 1)));
}

void DaemonProcess::signal(int signal_number) {
  if (pid_ > 0 && !exit_status_) ::kill(pid_, signal_number);
}

std::optional<int> DaemonProcess::wait(std::chrono::milliseconds limit) {
  if (exit_status_) return exit_status_;
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {  // looks at least once, so a zero limit asks "has it exited?"
    int status = 0;
    const pid_t done = ::waitpid(pid_, &status, WNOHANG);
    if (done == pid_) {
      exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      return exit_status_;
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

bool DaemonProcess::alive() {
  if (pid_ <= 0 || exit_status_) return false;
  return !wait(std::chrono::milliseconds(0)).has_value();
}

std::optional<std::uint64_t> DaemonProcess::rss_kib() const {
  std::ifstream status("/proc/" + std::to_string(pid_) + "/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6));
  }
  return std::nullopt;
}

std::string DaemonProcess::stderr_text() const {
  std::ifstream in(stderr_path_);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string minimal_scene_text() {
  return "objects:\n"
         "  - name: wall\n"
         "    box: {size_m: [0.2, 20, 6]}\n"
         "    pose: {position_m: [5.1, 0, 0]}\n"
         "    reflectance: 0.8\n";
}

}  // namespace ldoem::daemon::test
