// Loading a scene: YAML text -> validated Scene (docs/scenes.md is the file format).
// Every problem is a typed SceneError that says where it is (file:line:column of the YAML node,
// from yaml-cpp's Mark) and which key (`objects[2].box.size_m`). Nothing here throws.
#pragma once

#include "ldoem/base/expected.hpp"
#include "ldoem/scene/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace ldoem::scene {

enum class SceneErrorKind : std::uint8_t {
  io,                // the scene file cannot be read
  syntax,            // not YAML
  unknown_key,       // a key the format does not define (typos are errors, not warnings)
  duplicate_key,     // the same key twice in one map
  missing_key,       // a required key is absent
  conflicting_keys,  // two keys that exclude each other (rpy_deg and quaternion_wxyz, ...)
  wrong_type,        // a map where a number belongs, text where a number belongs, ...
  not_finite,        // NaN or infinity
  out_of_range,      // negative size, reflectance outside [0, 1], ...
  mesh,              // a mesh file missing, unreadable or without triangles (assimp)
  unknown_effect,    // an effect name D9 does not list
  unknown_fault,     // a fault kind D11 does not list
  unknown_service,   // a service name spec 3.2 does not list (fault triggers)
  internal,          // anything else (out of memory): reported, never thrown
};

struct SceneError {
  SceneErrorKind kind = SceneErrorKind::internal;
  std::string file;      // display name of the scene
  int line = 0;          // 1-based; 0 when no position is known
  int column = 0;        // 1-based; 0 when no position is known
  std::string key_path;  // e.g. "objects[2].box.size_m"; empty for whole-file errors
  std::string detail;    // e.g. "must be positive"

  // "scenes/x.yaml:12:7: objects[2].box.size_m: must be positive"
  std::string message() const;
};

std::string_view to_string(SceneErrorKind kind);

using SceneResult = base::Expected<Scene, SceneError>;

// Limits on what one scene may ask for (docs/scenes.md): beyond them loading fails with
// out_of_range (or io for the file size) instead of exhausting memory.
inline constexpr std::size_t kMaxSceneObjects = 100'000;
inline constexpr std::size_t kMaxSceneTriangles = 4'000'000;
inline constexpr std::size_t kMaxSceneVertices = 12'000'000;
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{64} << 20;
// Every `*_step_s` (world.world_step_s, tilt_motor.world_step_s): finer than 1 us costs without
// a use and stalls the loop (1e-9 s took over 100 s per LPT pulse, issue 27 D5); coarser than
// 0.1 s lets a body fall through a floor in one step.
inline constexpr double kMinSceneStep_s = 1e-6;
inline constexpr double kMaxSceneStep_s = 0.1;
// Issue 27 (D6): yaml-cpp's node tree costs about 470 bytes per node (2e6 nodes: 940 MB peak),
// so the node count, not the file size, bounds the loader's memory: 1e6 nodes stay under half
// the units' MemoryMax=1G. Counted on a streaming parse before the tree is built, as are the
// objects and each waypoints list. 1e5 objects with a pose are 1.2e6 nodes, beyond it; a YAML
// alias (`- *crate`) is one node.
inline constexpr std::size_t kMaxSceneYamlNodes = 1'000'000;
inline constexpr std::size_t kMaxWaypoints = 100'000;  // in one waypoints list
// YAML aliases can repeat one waypoints list on every object: the total is bounded too.
inline constexpr std::size_t kMaxSceneWaypoints = 1'000'000;

// Reads and validates a scene file. Mesh paths are resolved relative to the file's folder.
[[nodiscard]] SceneResult load_scene(const std::filesystem::path& path);

// The same from text. display_name appears in error messages and, if it names a file path,
// mesh paths are resolved relative to its folder (so passing the real path gives the same
// result as load_scene); otherwise relative to the current directory.
[[nodiscard]] SceneResult load_scene_from_string(std::string_view yaml, std::string_view display_name);

// D9 names, as written in scenes ("noise", "mixed_pixels", ...).
std::string_view effect_name(Effect effect);

}  // namespace ldoem::scene
