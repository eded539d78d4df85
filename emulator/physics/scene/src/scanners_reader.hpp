// The `scanners:` list of a scene with several scanners (issue 15, docs/scenes.md "Several
// scanners"). Internal to ldoem_scene.
#pragma once

#include "yaml_fields.hpp"

#include <vector>

namespace ldoem::scene::detail {

// A list of D9/D13 effect names at `path` (defined in scene_loader.cpp).
EffectSet read_effects(const std::string& file, const YAML::Node& node, const std::string& path);

// fog_returns needs the waveform and atmosphere effects: a located error otherwise.
void check_fog_returns(const std::string& file, const YAML::Node& section, const std::string& path,
                       const ScannerConfig& scanner, const EffectSet& effects);

// Each entry is a `scanner:` section plus name, effects (else `scene_effects`), flash_file and
// endpoints. Duplicate names, TCP ports, CAN identifiers, pty paths and flash files are errors.
std::vector<ScannerEntry> read_scanners(const std::string& file, const YAML::Node& node,
                                        const EffectSet& scene_effects);

}  // namespace ldoem::scene::detail
