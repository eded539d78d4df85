#include "ldoem/daemon/flash_start.hpp"

#include "ldoem/daemon/file_flash_store.hpp"
#include "ldoem/plant/scene_device_defaults.hpp"

namespace ldoem::daemon {

base::Expected<StartedFlash, StartFailure> start_flash(const Options& device_options, bool reset_flash,
                                                       const scene::Scene& view, const endpoints::Logger& logger) {
  using base::Unexpected;
  StartedFlash started{nullptr, plant::device_config_from(view.scanner.flash)};
  const std::string where = "flash " + device_options.flash_path.string();
  const std::string remedy = "; fix or remove the file, or start with --reset-flash to replace it with the scene's defaults (D4)";
  const std::string resetting = "; --reset-flash: starting from the scene's defaults (D4)";
  if (device_options.flash_mode == FlashMode::memory) {
    started.store = std::make_unique<control::MemoryFlashStore>();
  } else {
    auto file = std::make_unique<FileFlashStore>(device_options.flash_path);
    if (auto note = file->remove_stale_temporaries()) logger.log(endpoints::LogLevel::info, *note);  // issue 27 D13
    auto image = file->read();
    started.store = std::move(file);
    if (!image) {
      if (!reset_flash) return Unexpected(StartFailure{kExitUsageError, where + ": " + image.error() + remedy});
      logger.log(endpoints::LogLevel::warn, where + ": " + image.error() + resetting);
      return started;
    }
  }
  const control::FlashLoadResult loaded = control::load_flash_or(*started.store, started.config);
  if (!loaded.problem || loaded.problem->kind == control::FlashErrorKind::empty) {
    started.config = loaded.config;
    return started;
  }
  const std::string problem = where + ":" + std::to_string(loaded.problem->line) + ": " +
                              std::string(control::describe(loaded.problem->kind));
  if (!reset_flash) return Unexpected(StartFailure{kExitUsageError, problem + remedy});
  logger.log(endpoints::LogLevel::warn, problem + resetting);
  return started;
}

}  // namespace ldoem::daemon
