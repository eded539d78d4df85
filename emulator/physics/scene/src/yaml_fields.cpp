#include "yaml_fields.hpp"

#include <charconv>
#include <cmath>
#include <utility>

namespace ldoem::scene::detail {

void fail(const std::string& file, SceneErrorKind kind, const YAML::Node& at,
          const std::string& key_path, std::string detail) {
  SceneError error;
  error.kind = kind;
  error.file = file;
  // yaml-cpp marks are 0-based and -1 when unknown (null or absent nodes).
  const YAML::Mark mark = at.IsDefined() ? at.Mark() : YAML::Mark::null_mark();
  if (mark.line >= 0 && mark.column >= 0) {
    error.line = mark.line + 1;
    error.column = mark.column + 1;
  }
  error.key_path = key_path;
  error.detail = std::move(detail);
  throw LoadFailure{std::move(error)};
}

MapReader::MapReader(const std::string& file, const YAML::Node& node, std::string path)
    : file_(file), node_(node), path_(std::move(path)) {
  if (!node.IsMap()) fail(file_, SceneErrorKind::wrong_type, node, path_, "must be a map");
  for (const auto& item : node) {
    std::string key;
    if (!item.first.IsScalar()) {
      fail(file_, SceneErrorKind::wrong_type, item.first, path_, "keys must be plain text");
    }
    key = item.first.Scalar();
    for (const Entry& seen : entries_) {
      if (seen.key == key) {
        fail(file_, SceneErrorKind::duplicate_key, item.first, child_path(key), "duplicate key");
      }
    }
    entries_.push_back(Entry{key, item.first, item.second, false});
  }
}

std::string MapReader::child_path(std::string_view key) const {
  if (path_.empty()) return std::string(key);
  return path_ + "." + std::string(key);
}

std::optional<YAML::Node> MapReader::get(std::string_view key) {
  for (Entry& entry : entries_) {
    if (entry.key == key) {
      entry.used = true;
      return entry.value;
    }
  }
  return std::nullopt;
}

YAML::Node MapReader::require(std::string_view key) {
  if (auto value = get(key)) return *value;
  fail(file_, SceneErrorKind::missing_key, node_, child_path(key), "is required");
}

bool MapReader::has(std::string_view key) const {
  for (const Entry& entry : entries_) {
    if (entry.key == key) return true;
  }
  return false;
}

void MapReader::finish() const {
  for (const Entry& entry : entries_) {
    if (!entry.used) {
      fail(file_, SceneErrorKind::unknown_key, entry.key_node, child_path(entry.key), "unknown key");
    }
  }
}

namespace {

void check_constraint(const std::string& file, const YAML::Node& node, const std::string& path,
                      double value, Constraint constraint) {
  switch (constraint) {
    case Constraint::finite:
      return;
    case Constraint::positive:
      if (!(value > 0.0)) fail(file, SceneErrorKind::out_of_range, node, path, "must be positive");
      return;
    case Constraint::non_negative:
      if (!(value >= 0.0)) fail(file, SceneErrorKind::out_of_range, node, path, "must be >= 0");
      return;
    case Constraint::unit_interval:
      if (!(value >= 0.0 && value <= 1.0)) {
        fail(file, SceneErrorKind::out_of_range, node, path, "must be in [0, 1]");
      }
      return;
    case Constraint::below_one:
      if (!(value >= 0.0 && value < 1.0)) {
        fail(file, SceneErrorKind::out_of_range, node, path, "must be in [0, 1)");
      }
      return;
  }
}

}  // namespace

double read_double(const std::string& file, const YAML::Node& node, const std::string& path,
                   Constraint constraint) {
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value)) {
    fail(file, SceneErrorKind::wrong_type, node, path, "must be a number");
  }
  if (!std::isfinite(value)) fail(file, SceneErrorKind::not_finite, node, path, "must be finite");
  // ODE squares lengths and coordinates: beyond this its arithmetic overflows (docs/scenes.md).
  if (std::abs(value) > kMaxSceneNumber) {
    fail(file, SceneErrorKind::out_of_range, node, path, "must be within +-1e9");
  }
  check_constraint(file, node, path, value, constraint);
  return value;
}

std::uint64_t read_unsigned(const std::string& file, const YAML::Node& node,
                            const std::string& path, std::uint64_t min_value,
                            std::uint64_t max_value) {
  const std::string range_text =
      "must be an integer in [" + std::to_string(min_value) + ", " + std::to_string(max_value) + "]";
  if (!node.IsScalar()) fail(file, SceneErrorKind::wrong_type, node, path, range_text);
  std::string_view text = node.Scalar();
  if (!text.empty() && text.front() == '-') {
    fail(file, SceneErrorKind::out_of_range, node, path, range_text);
  }
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  int base = 10;
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    text.remove_prefix(2);
    base = 16;
  }
  std::uint64_t value = 0;
  const auto [end, status] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (status == std::errc::result_out_of_range) {
    fail(file, SceneErrorKind::out_of_range, node, path, range_text);
  }
  if (status != std::errc() || end != text.data() + text.size() || text.empty()) {
    fail(file, SceneErrorKind::wrong_type, node, path, range_text);
  }
  if (value < min_value || value > max_value) {
    fail(file, SceneErrorKind::out_of_range, node, path, range_text);
  }
  return value;
}

std::string read_string(const std::string& file, const YAML::Node& node, const std::string& path) {
  if (!node.IsScalar()) fail(file, SceneErrorKind::wrong_type, node, path, "must be text");
  return node.Scalar();
}

void require_sequence(const std::string& file, const YAML::Node& node, const std::string& path) {
  if (!node.IsSequence()) fail(file, SceneErrorKind::wrong_type, node, path, "must be a list");
}

Eigen::Vector3d read_vector3(const std::string& file, const YAML::Node& node,
                             const std::string& path, Constraint constraint) {
  if (!node.IsSequence() || node.size() != 3) {
    fail(file, SceneErrorKind::wrong_type, node, path, "must be a list of 3 numbers");
  }
  Eigen::Vector3d value;
  for (std::size_t i = 0; i < 3; ++i) {
    value[static_cast<Eigen::Index>(i)] =
        read_double(file, node[i], path + "[" + std::to_string(i) + "]", constraint);
  }
  return value;
}

void read_field(MapReader& map, std::string_view key, double& out, Constraint constraint) {
  if (auto node = map.get(key)) out = read_double(map.file(), *node, map.child_path(key), constraint);
}

void read_field(MapReader& map, std::string_view key, std::string& out) {
  if (auto node = map.get(key)) out = read_string(map.file(), *node, map.child_path(key));
}

void read_field(MapReader& map, std::string_view key, bool& out) {
  if (auto node = map.get(key)) {
    const std::string text = read_string(map.file(), *node, map.child_path(key));
    if (text != "true" && text != "false") {
      fail(map.file(), SceneErrorKind::wrong_type, *node, map.child_path(key), "must be true or false");
    }
    out = text == "true";
  }
}

void read_field(MapReader& map, std::string_view key, Eigen::Vector3d& out, Constraint constraint) {
  if (auto node = map.get(key)) out = read_vector3(map.file(), *node, map.child_path(key), constraint);
}

void read_step(MapReader& map, std::string_view key, double& step_s) {
  const auto node = map.get(key);
  if (!node) return;
  step_s = read_double(map.file(), *node, map.child_path(key), Constraint::positive);
  if (step_s < kMinSceneStep_s || step_s > kMaxSceneStep_s) {
    fail(map.file(), SceneErrorKind::out_of_range, *node, map.child_path(key), "must be in [1e-6, 0.1] s");
  }
}

}  // namespace ldoem::scene::detail
