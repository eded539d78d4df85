// ldoem-emud: parse the command line, then run_daemon (load the scene, open the endpoints, run
// the loop, map the outcome to an exit code; design.md convention 1). Everything it decides is
// in ldoem_daemon.
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <stdexcept>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

#include "ldoem/base/command_line.hpp"
#include "ldoem/daemon/options.hpp"
#include "ldoem/daemon/run_daemon.hpp"

namespace {

int run_emud(int argc, char** argv) {
  using namespace ldoem::daemon;
  const std::vector<std::string_view> arguments(argv + 1, argv + argc);
  const auto command = parse_command_line(arguments);
  if (!command) {
    std::cerr << ldoem::base::usage_error_line("ldoem-emud", command.error().message);
    return kExitUsageError;
  }
  if (command->kind == CommandKind::help_all) {
    std::cout << usage_text("ldoem-emud");
    return 0;
  }
  if (command->kind == CommandKind::help) {
    std::cout << brief_usage_text("ldoem-emud");
    return kExitOk;
  }
  if (command->kind == CommandKind::version) {
    std::cout << version_text();
    return kExitOk;
  }
  if (command->kind == CommandKind::completion) {
    std::cout << command->completion_script;
    return kExitOk;
  }
  return run_daemon("ldoem-emud", command->options);
}

}  // namespace

// Out of memory anywhere (a huge scene, RLIMIT_AS, a cgroup's MemoryMax) ends with a message
// and exit 1, never with std::terminate's abort (134) and a core dump (issue 11).
int main(int argc, char** argv) {
  try {
    return run_emud(argc, argv);
  } catch (const std::bad_alloc&) {
    std::cerr << "ldoem-emud: out of memory\n";
  } catch (const std::exception& error) {
    std::cerr << "ldoem-emud: " << error.what() << '\n';
  }
  return ldoem::daemon::kExitRuntimeFailure;
}
