#include "fault_reader.hpp"

#include "yaml_fields.hpp"

namespace ldoem::scene::detail {
namespace {

SceneErrorKind scene_error_kind(faults::FieldErrorKind kind) {
  switch (kind) {
    case faults::FieldErrorKind::unknown_key: return SceneErrorKind::unknown_key;
    case faults::FieldErrorKind::unknown_kind: return SceneErrorKind::unknown_fault;
    case faults::FieldErrorKind::unknown_service: return SceneErrorKind::unknown_service;
    case faults::FieldErrorKind::wrong_type: return SceneErrorKind::wrong_type;
    case faults::FieldErrorKind::out_of_range: return SceneErrorKind::out_of_range;
    case faults::FieldErrorKind::missing_key: return SceneErrorKind::missing_key;
    case faults::FieldErrorKind::conflicting_keys: return SceneErrorKind::conflicting_keys;
  }
  return SceneErrorKind::internal;
}

// YAML scalars are text; the grammar wants a number wherever the text is one.
faults::FieldValue field_value(const std::string& file, const YAML::Node& node, const std::string& path) {
  if (!node.IsScalar()) fail(file, SceneErrorKind::wrong_type, node, path, "must be a number or a name");
  double number = 0.0;
  if (YAML::convert<double>::decode(node, number) && node.Tag() != "!") return number;
  return node.Scalar();
}

struct Located {
  std::string key;  // flattened ("on.nth")
  YAML::Node node;
};

faults::FaultSpec read_entry(const std::string& file, const YAML::Node& node, const std::string& path) {
  if (!node.IsMap()) fail(file, SceneErrorKind::wrong_type, node, path, "must be a map");
  MapReader duplicate_check(file, node, path);  // rejects duplicate keys with their position
  faults::FaultEntryBuilder builder;
  std::vector<Located> keys;
  auto apply = [&](const std::string& key, const YAML::Node& value) {
    keys.push_back(Located{key, value});
    const std::string key_path = path + "." + key;
    if (auto problem = builder.set(key, field_value(file, value, key_path))) {
      fail(file, scene_error_kind(problem->kind), value, key_path, problem->detail);
    }
  };
  for (const auto& item : node) {
    const std::string key = item.first.Scalar();
    if (faults::FaultEntryBuilder::is_trigger_map(key)) {
      MapReader members(file, item.second, path + "." + key);
      for (const auto& member : item.second) apply(key + "." + member.first.Scalar(), member.second);
    } else {
      apply(key, item.second);
    }
  }
  auto finished = builder.finish();
  if (auto* problem = std::get_if<faults::FieldError>(&finished)) {
    YAML::Node at = node;
    for (const Located& located : keys) {
      if (located.key == problem->key) at = located.node;
    }
    fail(file, scene_error_kind(problem->kind), at, problem->key.empty() ? path : path + "." + problem->key,
         problem->detail);
  }
  return std::get<faults::FaultSpec>(finished);
}

}  // namespace

std::vector<faults::FaultSpec> read_faults(const std::string& file, const YAML::Node& node) {
  require_sequence(file, node, "faults");
  std::vector<faults::FaultSpec> entries;
  for (std::size_t i = 0; i < node.size(); ++i) {
    entries.push_back(read_entry(file, node[i], "faults[" + std::to_string(i) + "]"));
  }
  return entries;
}

}  // namespace ldoem::scene::detail
