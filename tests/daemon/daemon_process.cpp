#include "daemon_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <utility>

namespace ldoem::daemon::test {

std::optional<DaemonProcess> DaemonProcess::start(const std::vector<std::string>& arguments) {
  return start_program(LDOEM_EMUD_PATH, arguments);
}

std::optional<DaemonProcess> DaemonProcess::start_program(const std::string& program,
                                                          const std::vector<std::string>& arguments) {
  char stderr_template[] = "/tmp/ldoem-emud-stderr-XXXXXX";
  const int stderr_fd = ::mkostemp(stderr_template, O_CLOEXEC);
  if (stderr_fd < 0) return std::nullopt;
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    ::close(stderr_fd);
    ::unlink(stderr_template);
    return std::nullopt;
  }
  std::vector<std::string> argv{program};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  test_support::ChildSetup setup;
  setup.out.fd = pipe_fds[1];
  setup.err.fd = stderr_fd;
  auto child = test_support::Child::spawn(argv, setup);
  ::close(pipe_fds[1]);
  ::close(stderr_fd);
  if (!child) {
    ::close(pipe_fds[0]);
    ::unlink(stderr_template);
    return std::nullopt;
  }
  return DaemonProcess(std::move(*child), pipe_fds[0], stderr_template);
}

DaemonProcess::DaemonProcess(DaemonProcess&& other) noexcept
    : child_(std::move(other.child_)),
      stdout_fd_(std::exchange(other.stdout_fd_, -1)),
      stderr_path_(std::move(other.stderr_path_)),
      stdout_(std::move(other.stdout_)),
      endpoints_(std::move(other.endpoints_)) {
  other.stderr_path_.clear();
}

DaemonProcess::~DaemonProcess() {
  child_.kill_now();
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

std::optional<int> DaemonProcess::wait(std::chrono::milliseconds limit) { return child_.wait(limit); }

bool DaemonProcess::alive() { return child_.pid() > 0 && !child_.exited(); }

std::optional<std::uint64_t> DaemonProcess::rss_kib() const {
  std::ifstream status("/proc/" + std::to_string(child_.pid()) + "/status");
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
