#include "ldoem/test_support/child.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <thread>
#include <utility>

extern char** environ;

namespace ldoem::test_support {
namespace {

constexpr std::chrono::milliseconds kPollInterval{10};

void redirect(posix_spawn_file_actions_t& actions, const ChildStream& stream, int target) {
  if (stream.fd >= 0) {
    posix_spawn_file_actions_adddup2(&actions, stream.fd, target);
  } else if (!stream.path.empty()) {
    posix_spawn_file_actions_addopen(&actions, target, stream.path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  }
}

}  // namespace

int exit_status_of(int wait_status) {
  if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
  if (WIFSIGNALED(wait_status)) return 128 + WTERMSIG(wait_status);
  return -1;
}

std::optional<Child> Child::spawn(const std::vector<std::string>& argv, const ChildSetup& setup) {
  if (argv.empty()) return std::nullopt;
  std::vector<std::string> argv_text = argv;
  std::vector<char*> args;
  for (std::string& text : argv_text) args.push_back(text.data());
  args.push_back(nullptr);

  std::vector<std::string> env_text;
  for (char** entry = environ; *entry != nullptr; ++entry) env_text.emplace_back(*entry);
  env_text.insert(env_text.end(), setup.environment.begin(), setup.environment.end());
  std::vector<char*> envp;
  for (std::string& text : env_text) envp.push_back(text.data());
  envp.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  redirect(actions, setup.out, STDOUT_FILENO);
  redirect(actions, setup.err, STDERR_FILENO);
  // The daemon wants its signals' defaults: none blocked, whatever the test runner blocks.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  pid_t pid = -1;
  const int error = ::posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), envp.data());
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) return std::nullopt;
  return Child(pid);
}

Child::Child(Child&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)), exit_status_(other.exit_status_) {}

Child::~Child() {
  if (pid_ > 0 && !exit_status_) kill_now();
}

bool Child::exited() {
  if (exit_status_) return true;
  if (pid_ <= 0) return false;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
  exit_status_ = exit_status_of(status);
  return true;
}

std::optional<int> Child::wait(std::chrono::milliseconds limit) {
  const auto give_up = std::chrono::steady_clock::now() + limit;
  while (!exited()) {  // looks at least once
    if (std::chrono::steady_clock::now() >= give_up) return std::nullopt;
    std::this_thread::sleep_for(kPollInterval);
  }
  return exit_status_;
}

int Child::stop(std::chrono::milliseconds grace) {
  if (pid_ <= 0) return -1;
  if (!exited()) {
    ::kill(pid_, SIGTERM);
    if (!wait(grace)) kill_now();
  }
  return *exit_status_;
}

void Child::kill_now() {
  if (pid_ <= 0 || exit_status_) return;
  ::kill(pid_, SIGKILL);
  int status = 0;
  if (::waitpid(pid_, &status, 0) == pid_) {
    exit_status_ = exit_status_of(status);
  } else {
    exit_status_ = 128 + SIGKILL;
  }
}

void Child::signal(int signal_number) {
  if (pid_ > 0 && !exit_status_) ::kill(pid_, signal_number);
}

}  // namespace ldoem::test_support
