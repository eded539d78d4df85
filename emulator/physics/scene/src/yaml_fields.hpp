// Typed, path-aware readers over yaml-cpp nodes for the scene loader. Internal to ldoem_scene.
// A failed check throws LoadFailure, which only load_scene_from_string catches: inside the
// loader this keeps each field one line; at the API boundary it becomes a SceneError value.
#pragma once

#include "ldoem/scene/scene_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ldoem::scene::detail {

struct LoadFailure {
  SceneError error;
};

[[noreturn]] void fail(const std::string& file, SceneErrorKind kind, const YAML::Node& at,
                       const std::string& key_path, std::string detail);

// One YAML map: every key must be asked for once (by get/require) before finish(), which
// rejects the keys nobody asked for. Duplicate keys are rejected on construction.
class MapReader {
 public:
  MapReader(const std::string& file, const YAML::Node& node, std::string path);

  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }
  std::string child_path(std::string_view key) const;

  std::optional<YAML::Node> get(std::string_view key);
  YAML::Node require(std::string_view key);
  bool has(std::string_view key) const;
  void finish() const;

 private:
  struct Entry {
    std::string key;
    YAML::Node key_node;
    YAML::Node value;
    bool used = false;
  };
  std::string file_;
  YAML::Node node_;
  std::string path_;
  std::vector<Entry> entries_;
};

// No number in a scene (coordinate, size, constant) may exceed this in magnitude.
inline constexpr double kMaxSceneNumber = 1e9;

enum class Constraint : std::uint8_t {
  finite,          // any finite number
  positive,        // > 0
  non_negative,    // >= 0
  unit_interval,   // [0, 1]
  below_one,       // [0, 1)
};

double read_double(const std::string& file, const YAML::Node& node, const std::string& path,
                   Constraint constraint = Constraint::finite);
std::uint64_t read_unsigned(const std::string& file, const YAML::Node& node,
                            const std::string& path, std::uint64_t min_value,
                            std::uint64_t max_value);
std::string read_string(const std::string& file, const YAML::Node& node, const std::string& path);
Eigen::Vector3d read_vector3(const std::string& file, const YAML::Node& node,
                             const std::string& path, Constraint constraint = Constraint::finite);
// A sequence node, or a wrong_type failure.
void require_sequence(const std::string& file, const YAML::Node& node, const std::string& path);

// Optional fields of a map: leave `out` unchanged when the key is absent.
void read_field(MapReader& map, std::string_view key, double& out,
                Constraint constraint = Constraint::finite);
void read_field(MapReader& map, std::string_view key, std::string& out);
// true or false only (YAML's yes/no/on/off spellings are refused: a typo must not flip a flag).
void read_field(MapReader& map, std::string_view key, bool& out);
void read_field(MapReader& map, std::string_view key, Eigen::Vector3d& out,
                Constraint constraint = Constraint::finite);
template <class Unsigned>
void read_field(MapReader& map, std::string_view key, Unsigned& out, std::uint64_t min_value,
                std::uint64_t max_value) {
  if (auto node = map.get(key)) {
    out = static_cast<Unsigned>(read_unsigned(map.file(), *node, map.child_path(key), min_value,
                                              max_value));
  }
}

// A `*_step_s` key: in [kMinSceneStep_s, kMaxSceneStep_s] (scene_loader.hpp), else a located
// out_of_range error. Left as it is when absent.
void read_step(MapReader& map, std::string_view key, double& step_s);

}  // namespace ldoem::scene::detail
