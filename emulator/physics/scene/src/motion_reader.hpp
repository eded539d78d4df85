// D12 scene keys: an object's or the pivot's `motion`, an object's `dynamics`, the top-level
// `world`. Internal to ldoem_scene; docs/scenes.md "Moving objects" is the format.
#pragma once

#include "yaml_fields.hpp"

namespace ldoem::scene::detail {

Motion read_motion(const std::string& file, const YAML::Node& node, const std::string& path);
Dynamics read_dynamics(const std::string& file, const YAML::Node& node, const std::string& path);
WorldConfig read_world(const std::string& file, const YAML::Node& node, const std::string& path);

}  // namespace ldoem::scene::detail
