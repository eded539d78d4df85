// The `scanner:` (alias `device:`, D3) section of a scene. Internal to ldoem_scene.
#pragma once

#include "yaml_fields.hpp"

namespace ldoem::scene::detail {

// Starts from the defaults in scene.hpp and overrides what the section gives; also sets
// optics.calibration per D6 (optics.hpp).
ScannerConfig read_scanner(const std::string& file, const YAML::Node& node, const std::string& path);
// The same keys from a map the caller reads further (a `scanners:` entry) and finishes itself.
ScannerConfig read_scanner_fields(MapReader& map);

}  // namespace ldoem::scene::detail
