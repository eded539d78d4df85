#include "ldoem/daemon/run_daemon.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/daemon/daemon.hpp"
#include "ldoem/daemon/device_instance.hpp"
#include "ldoem/daemon/realtime.hpp"
#include "ldoem/recording/recording_tap.hpp"
#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::daemon {

int run_daemon(std::string_view program, const Options& options) {
  const std::string prefix = std::string(program) + ": ";
  // --replay: the recorded device needs no scene; the empty one gives the world nothing to hit.
  scene::SceneResult loaded = options.replay_path ? scene::SceneResult(scene::Scene{}) : scene::load_scene(options.scene_path);
  if (!loaded) {
    std::cerr << prefix << loaded.error().message() << '\n';
    return kExitUsageError;
  }
  // The flash is written at the first flash change and at exit: a folder that is not there
  // would lose it only then, so say so before starting.
  if (std::error_code error; options.flash_dir && !std::filesystem::is_directory(*options.flash_dir, error)) {
    std::cerr << prefix + "--flash-dir " << options.flash_dir->string() << ": not a folder\n";
    return kExitUsageError;
  }
  if (const auto failed = make_default_flash_folder(options)) {
    std::cerr << prefix << *failed << '\n';
    return kExitUsageError;
  }
  if (options.flash_mode == FlashMode::file && !options.flash_dir) {
    const std::filesystem::path folder =
        options.flash_path.has_parent_path() ? options.flash_path.parent_path() : std::filesystem::path(".");
    if (std::error_code error; !std::filesystem::is_directory(folder, error)) {
      std::cerr << prefix + "--flash " << options.flash_path.string() << ": the folder " << folder.string()
                << " does not exist\n";
      return kExitUsageError;
    }
  }
  // --record: the capture is open before the first telegram can arrive.
  std::unique_ptr<capture::CaptureWriter> recording;
  if (options.record_path) {
    auto writer = capture::CaptureWriter::open(
        {*options.record_path, options.record_max_bytes, options.record_files, "ldoem-emud"});
    if (!writer) {
      std::cerr << prefix + "--record: " << writer.error() << '\n';
      return kExitUsageError;
    }
    recording = std::move(*writer);
  }
  auto daemon = Daemon::create(options, std::move(*loaded), std::cout, std::cerr);
  if (!daemon) {
    std::cerr << prefix << daemon.error().message << '\n';
    return daemon.error().exit_code;
  }
  if (options.realtime) {
    // After the scene is loaded, so mlockall's MCL_CURRENT holds it; before the loop runs.
    std::cerr << prefix << request_realtime().message << '\n';
  }
  const endpoints::Logger logger(std::cerr, options.log_level);
  std::optional<recording::RecordingTap> tap;
  if (recording) {
    // CAN frames are recorded on the first identifier pair (D1: --can IF:REQ:RESP, else the flash's).
    const auto& can = (*daemon)->device().can_config();
    capture::RecorderCanIds ids{can.request_id, can.response_id};
    if (!options.can_id_pairs.empty()) ids = {options.can_id_pairs.front().request_id, options.can_id_pairs.front().response_id};
    // The fault tap (D11), when there is one, comes after: the capture shows what it did.
    tap.emplace(*recording, ids, logger, (*daemon)->device().wire_tap());
    (*daemon)->device().set_wire_tap(&*tap);
  }
  return (*daemon)->run();
}

}  // namespace ldoem::daemon
