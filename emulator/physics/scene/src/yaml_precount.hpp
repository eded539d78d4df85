// Issue 27 (D6): a scene's size checked before its node tree is built. yaml-cpp's node tree costs
// a few hundred bytes per node, so a 58 MB file of sphere lines grew to 5.9 GB before the object
// limit was checked on the tree. This pass reads the same text as a stream of parser events,
// with memory proportional to the nesting depth only, and stops at the first count past a limit
// with a located error. Internal to ldoem_scene.
#pragma once

#include <string>
#include <string_view>

namespace ldoem::scene::detail {

// Throws LoadFailure (out_of_range) when the text has more YAML nodes than kMaxSceneYamlNodes,
// more than kMaxSceneObjects items under the top-level `objects:`, or more than kMaxWaypoints
// items in one `waypoints:` list. Syntax errors are left to the full parse (yaml-cpp throws
// them here too; the caller catches both the same way).
void precount_yaml(std::string_view text, const std::string& file);

}  // namespace ldoem::scene::detail
