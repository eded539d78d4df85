#include "ldoem/daemon/scanner_options.hpp"

#include <string>

namespace ldoem::daemon {
namespace {

using base::Unexpected;

std::filesystem::path default_flash_path(const Options& options) {
  std::filesystem::path path = flash_folder(options) / options.scene_path.filename();
  path += std::string(kFlashFileSuffix);
  return path;
}

// flash_file relative to the flash folder (an absolute one stays), else <scene>.<name>.flash.
std::filesystem::path entry_flash_path(const Options& options, const scene::ScannerEntry& entry) {
  if (entry.flash_file) return flash_folder(options) / *entry.flash_file;
  std::filesystem::path path = flash_folder(options) / options.scene_path.filename();
  path += "." + entry.name + std::string(kFlashFileSuffix);
  return path;
}

// The entry's endpoints where `options` has none of that kind.
void fill_from_entry(Options& options, const scene::ScannerEntry& entry) {
  const scene::ScannerEndpoints& endpoints = entry.endpoints;
  if (!options.tcp && endpoints.tcp) options.tcp = TcpOption{endpoints.tcp->address, endpoints.tcp->port};
  if (options.can_interface && options.can_id_pairs.empty() && endpoints.can_ids) {
    options.can_id_pairs.push_back(CanIdPair{(*endpoints.can_ids)[0], (*endpoints.can_ids)[1]});
  }
  if (!options.serial_pty && endpoints.serial_pty) options.serial_pty = std::filesystem::path(*endpoints.serial_pty);
  if (!options.lpt && endpoints.lpt) {
    options.lpt = LptOption{endpoints.lpt->gpio ? LptBackend::gpio : LptBackend::pty, endpoints.lpt->target};
  }
}

}  // namespace

base::Expected<std::vector<Options>, UsageError> scanner_options(const Options& options, const scene::Scene& scene) {
  const bool flash_given = options.flash_mode == FlashMode::file && options.flash_path != default_flash_path(options);
  // One daemon serves one CAN bus: a scanner's `can:` endpoint names that bus for its ids.
  for (std::size_t i = 0; i < scene.scanners.size(); ++i) {
    const scene::ScannerEndpoints& endpoints = scene.scanners[i].endpoints;
    if (endpoints.can_ids && options.can_interface && endpoints.can_interface != *options.can_interface) {
      return Unexpected(UsageError{"scanners[" + std::to_string(i) + "].endpoints.can: names " + endpoints.can_interface +
                                   " but the daemon's bus is --can can:" + *options.can_interface +
                                   " (one bus for all scanners)"});
    }
  }
  if (scene.scanners.size() <= 1) {
    Options single = options;
    if (!scene.scanners.empty()) {
      fill_from_entry(single, scene.scanners.front());
      if (!flash_given && single.flash_mode == FlashMode::file && scene.scanners.front().flash_file) {
        single.flash_path = entry_flash_path(options, scene.scanners.front());
      }
    }
    return std::vector<Options>{single};
  }
  const std::string several = " names one scanner's endpoint; with " + std::to_string(scene.scanners.size()) +
                              " scanners each has its own in the scene (scanners[i].endpoints, docs/scenes.md)";
  if (options.tcp) return Unexpected(UsageError{"--tcp:" + several});
  if (!options.can_id_pairs.empty()) return Unexpected(UsageError{"--can can:IF:REQ:RESP:" + several});
  if (options.serial_pty) return Unexpected(UsageError{"--serial:" + several});
  if (options.lpt) return Unexpected(UsageError{"--lpt:" + several});
  if (flash_given) return Unexpected(UsageError{"--flash: with several scanners each has its own (scanners[i].flash_file)"});
  if (options.record_path) return Unexpected(UsageError{"--record: records one scanner; not available with several"});
  std::vector<Options> all;
  all.reserve(scene.scanners.size());
  for (std::size_t i = 0; i < scene.scanners.size(); ++i) {
    const scene::ScannerEntry& entry = scene.scanners[i];
    Options scanner = options;
    fill_from_entry(scanner, entry);
    if (scanner.flash_mode == FlashMode::file) scanner.flash_path = entry_flash_path(options, entry);
    all.push_back(std::move(scanner));
  }
  return all;
}

std::string no_host_transport_error(const scene::Scene& scene, std::size_t scanner) {
  if (scene.scanners.size() <= 1) return "--no-can: no host transport left (add --tcp or --serial)";
  return "scanners[" + std::to_string(scanner) + "] (" + scene.scanners.at(scanner).name +
         "): no host transport: give endpoints.tcp or endpoints.serial in the scene, or use CAN";
}

}  // namespace ldoem::daemon
