// The scene's `faults:` list (D11, docs/faults.md): YAML maps handed field by field to the
// shared fault-entry grammar (ldoem/faults/fault_spec.hpp), errors located at the node.
#pragma once

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "ldoem/faults/fault_spec.hpp"

namespace ldoem::scene::detail {

std::vector<faults::FaultSpec> read_faults(const std::string& file, const YAML::Node& node);

}  // namespace ldoem::scene::detail
