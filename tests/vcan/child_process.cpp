#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <array>
#include <utility>

namespace ldoem::test {

std::optional<CapturedProcess> CapturedProcess::start(const std::vector<std::string>& argv) {
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    return std::nullopt;
  }
  test_support::ChildSetup setup;
  setup.out.fd = pipe_fds[1];
  auto child = test_support::Child::spawn(argv, setup);
  ::close(pipe_fds[1]);
  if (!child) {
    ::close(pipe_fds[0]);
    return std::nullopt;
  }
  return CapturedProcess(std::move(*child), pipe_fds[0]);
}

CapturedProcess::CapturedProcess(CapturedProcess&& other) noexcept
    : child_(std::move(other.child_)),
      stdout_fd_(std::exchange(other.stdout_fd_, -1)),
      output_(std::move(other.output_)) {}

CapturedProcess::~CapturedProcess() {
  child_.kill_now();
  if (stdout_fd_ >= 0) {
    ::close(stdout_fd_);
  }
}

void CapturedProcess::collect_output(std::chrono::milliseconds max_wait) {
  pollfd entry{stdout_fd_, POLLIN, 0};
  if (::poll(&entry, 1, static_cast<int>(max_wait.count())) <= 0) {
    return;
  }
  std::array<char, 4096> buffer{};
  const ssize_t got = ::read(stdout_fd_, buffer.data(), buffer.size());
  if (got > 0) {
    output_.append(buffer.data(), static_cast<std::size_t>(got));
  }
}

bool CapturedProcess::running() { return !child_.exited(); }

std::optional<int> CapturedProcess::wait(std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (running()) {
    if (std::chrono::steady_clock::now() > end) {
      child_.kill_now();
      return std::nullopt;
    }
    collect_output(std::chrono::milliseconds(20));
  }
  for (int i = 0; i < 100; ++i) {  // drain what it wrote before exiting
    const std::size_t before = output_.size();
    collect_output(std::chrono::milliseconds(0));
    if (output_.size() == before) {
      break;
    }
  }
  return child_.wait(std::chrono::milliseconds(0));
}

std::optional<int> run_program(const std::vector<std::string>& argv) {
  auto child = CapturedProcess::start(argv);
  if (!child) {
    return std::nullopt;
  }
  return child->wait(std::chrono::seconds(10));
}

}  // namespace ldoem::test
