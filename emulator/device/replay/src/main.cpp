// ldoem-replay: an alias of `ldoem-emud --replay CAPTURE` (docs/replay.md) with the command line
// it had before the daemon could replay: --speed is the daemon's --time-scale, --transport and
// --port are --replay-transport and --replay-port, CAN opens only when --can names it.
#include <iostream>
#include <new>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "ldoem/base/command_line.hpp"
#include "ldoem/daemon/run_daemon.hpp"
#include "ldoem/replay/replay_options.hpp"

namespace {

int run_replay(int argc, char** argv) {
  using namespace ldoem;
  const std::vector<std::string_view> arguments(argv + 1, argv + argc);
  auto options = replay::parse_replay_options(arguments);
  if (!options) {
    std::cerr << base::usage_error_line("ldoem-replay", options.error().message);
    return daemon::kExitUsageError;
  }
  if (options->completion_script) {
    std::cout << *options->completion_script;
    return daemon::kExitOk;
  }
  if (options->help_all || options->help) {
    std::cout << (options->help_all ? replay::replay_usage_text() : replay::replay_brief_usage_text());
    return daemon::kExitOk;
  }
  if (options->version) {
    std::cout << base::version_line("ldoem-replay");
    return daemon::kExitOk;
  }
  return daemon::run_daemon("ldoem-replay", replay::daemon_options(*options));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run_replay(argc, argv);
  } catch (const std::bad_alloc&) {
    std::cerr << "ldoem-replay: out of memory\n";
  } catch (const std::exception& error) {
    std::cerr << "ldoem-replay: " << error.what() << '\n';
  }
  return ldoem::daemon::kExitRuntimeFailure;
}
