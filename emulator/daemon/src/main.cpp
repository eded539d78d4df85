// ldoem-emud: parse the command line, load the scene, open the endpoints, run the loop, map the
// outcome to an exit code (STYLE.md section 1). Everything it decides is in ldoem_daemon.
#include <iostream>
#include <string_view>
#include <vector>

#include "ldoem/daemon/daemon.hpp"
#include "ldoem/daemon/options.hpp"
#include "ldoem/scene/scene_loader.hpp"

int main(int argc, char** argv) {
  using namespace ldoem::daemon;
  const std::vector<std::string_view> arguments(argv + 1, argv + argc);
  const auto command = parse_command_line(arguments);
  if (!command) {
    std::cerr << "ldoem-emud: " << command.error().message << '\n';
    return kExitUsageError;
  }
  if (command->kind == CommandKind::help) {
    std::cout << usage_text("ldoem-emud");
    return kExitOk;
  }
  if (command->kind == CommandKind::version) {
    std::cout << version_text();
    return kExitOk;
  }
  auto scene = ldoem::scene::load_scene(command->options.scene_path);
  if (!scene) {
    std::cerr << "ldoem-emud: " << scene.error().message() << '\n';
    return kExitUsageError;
  }
  auto daemon = Daemon::create(command->options, std::move(*scene), std::cout, std::cerr);
  if (!daemon) {
    std::cerr << "ldoem-emud: " << daemon.error().message << '\n';
    return daemon.error().exit_code;
  }
  return (*daemon)->run();
}
