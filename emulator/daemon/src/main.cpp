// ldoem-emud: parse the command line, load the scene, open the endpoints, run the loop, map the
// outcome to an exit code (design.md convention 1). Everything it decides is in ldoem_daemon.
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
#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/daemon/daemon.hpp"
#include "ldoem/daemon/device_instance.hpp"
#include "ldoem/recording/recording_tap.hpp"
#include "ldoem/daemon/options.hpp"
#include "ldoem/daemon/realtime.hpp"
#include "ldoem/scene/scene_loader.hpp"

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
  auto scene = ldoem::scene::load_scene(command->options.scene_path);
  if (!scene) {
    std::cerr << "ldoem-emud: " << scene.error().message() << '\n';
    return kExitUsageError;
  }
  const Options& options = command->options;
  // The flash is written at the first flash change and at exit: a folder that is not there
  // would lose it only then, so say so before starting.
  if (std::error_code error; options.flash_dir && !std::filesystem::is_directory(*options.flash_dir, error)) {
    std::cerr << "ldoem-emud: --flash-dir " << options.flash_dir->string() << ": not a folder\n";
    return kExitUsageError;
  }
  if (const auto failed = make_default_flash_folder(options)) {
    std::cerr << "ldoem-emud: " << *failed << '\n';
    return kExitUsageError;
  }
  if (options.flash_mode == FlashMode::file && !options.flash_dir) {
    const std::filesystem::path folder =
        options.flash_path.has_parent_path() ? options.flash_path.parent_path() : std::filesystem::path(".");
    if (std::error_code error; !std::filesystem::is_directory(folder, error)) {
      std::cerr << "ldoem-emud: --flash " << options.flash_path.string() << ": the folder " << folder.string()
                << " does not exist\n";
      return kExitUsageError;
    }
  }
  // --record: the capture is open before the first telegram can arrive.
  std::unique_ptr<ldoem::capture::CaptureWriter> recording;
  if (options.record_path) {
    auto writer = ldoem::capture::CaptureWriter::open(
        {*options.record_path, options.record_max_bytes, options.record_files, "ldoem-emud"});
    if (!writer) {
      std::cerr << "ldoem-emud: --record: " << writer.error() << '\n';
      return kExitUsageError;
    }
    recording = std::move(*writer);
  }
  auto daemon = Daemon::create(options, std::move(*scene), std::cout, std::cerr);
  if (!daemon) {
    std::cerr << "ldoem-emud: " << daemon.error().message << '\n';
    return daemon.error().exit_code;
  }
  if (options.realtime) {
    // After the scene is loaded, so mlockall's MCL_CURRENT holds it; before the loop runs.
    std::cerr << "ldoem-emud: " << request_realtime().message << '\n';
  }
  const ldoem::endpoints::Logger logger(std::cerr, options.log_level);
  std::optional<ldoem::recording::RecordingTap> tap;
  if (recording) {
    // CAN frames are recorded on the first identifier pair (D1: --can IF:REQ:RESP, else the flash's).
    const auto& can = (*daemon)->device().can_config();
    ldoem::capture::RecorderCanIds ids{can.request_id, can.response_id};
    if (!options.can_id_pairs.empty()) ids = {options.can_id_pairs.front().request_id, options.can_id_pairs.front().response_id};
    // The fault tap (D11), when there is one, comes after: the capture shows what it did.
    tap.emplace(*recording, ids, logger, (*daemon)->device().wire_tap());
    (*daemon)->device().set_wire_tap(&*tap);
  }
  return (*daemon)->run();
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
