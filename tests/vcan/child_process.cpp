#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <utility>

extern char** environ;

namespace ldoem::test {

std::optional<ChildProcess> ChildProcess::start(const std::vector<std::string>& argv) {
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    return std::nullopt;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
  std::vector<char*> args;
  for (const std::string& arg : argv) {
    args.push_back(const_cast<char*>(arg.c_str()));
  }
  args.push_back(nullptr);
  pid_t pid = -1;
  const int error = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (error != 0) {
    ::close(pipe_fds[0]);
    return std::nullopt;
  }
  return ChildProcess(pid, pipe_fds[0]);
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)),
      stdout_fd_(std::exchange(other.stdout_fd_, -1)),
      output_(std::move(other.output_)),
      exit_status_(other.exit_status_) {}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exit_status_) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  if (stdout_fd_ >= 0) {
    ::close(stdout_fd_);
  }
}

void ChildProcess::collect_output(std::chrono::milliseconds max_wait) {
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

bool ChildProcess::running() {
  if (exit_status_) {
    return false;
  }
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == pid_) {
    exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return false;
  }
  return true;
}

std::optional<int> ChildProcess::wait(std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (running()) {
    if (std::chrono::steady_clock::now() > end) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
      exit_status_ = 128 + SIGKILL;
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
  return exit_status_;
}

std::optional<int> run_program(const std::vector<std::string>& argv) {
  auto child = ChildProcess::start(argv);
  if (!child) {
    return std::nullopt;
  }
  return child->wait(std::chrono::seconds(10));
}

}  // namespace ldoem::test
