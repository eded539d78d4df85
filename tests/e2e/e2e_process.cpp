#include "e2e_process.hpp"

#include <sstream>
#include <thread>

namespace ldoem::e2e {
namespace {

constexpr std::chrono::milliseconds kPollInterval{20};

}  // namespace

std::optional<ChildProcess> ChildProcess::start(const std::string& program, const std::vector<std::string>& arguments,
                                                const std::string& log_prefix,
                                                const std::vector<std::string>& environment) {
  std::vector<std::string> argv{program};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  test_support::ChildSetup setup;
  setup.out.path = log_prefix + ".out";
  setup.err.path = log_prefix + ".err";
  setup.environment = environment;
  auto child = test_support::Child::spawn(argv, setup);
  if (!child) return std::nullopt;
  return ChildProcess(std::move(*child), log_prefix);
}

ChildProcess::~ChildProcess() {
  if (child_.pid() > 0 && !child_.exited()) child_.stop(std::chrono::seconds(2));
}

bool ChildProcess::wait_for_line(const std::string& text, bool in_stderr, std::chrono::milliseconds limit) {
  const auto give_up = std::chrono::steady_clock::now() + limit;
  for (;;) {
    // Only whole lines count: a line still being written ("listening on 127.0.0.1" before its
    // port) would otherwise match and be parsed half-written.
    std::istringstream lines(in_stderr ? stderr_text() : stdout_text());
    for (std::string line; std::getline(lines, line);) {
      if (lines.eof()) break;
      if (line.find(text) != std::string::npos) return true;
    }
    if (child_.exited() || std::chrono::steady_clock::now() >= give_up) return false;
    std::this_thread::sleep_for(kPollInterval);
  }
}

std::string ChildProcess::stdout_text() const { return read_file(log_prefix_ + ".out"); }
std::string ChildProcess::stderr_text() const { return read_file(log_prefix_ + ".err"); }

}  // namespace ldoem::e2e
