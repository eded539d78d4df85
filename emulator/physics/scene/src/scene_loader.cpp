// The scene file format is documented in docs/scenes.md; this file reads its top level and the
// `objects:` list. Internally a failed check throws detail::LoadFailure; the two API functions
// catch it (and yaml-cpp's and the standard library's exceptions) and return a SceneError.
#include "ldoem/scene/scene_loader.hpp"

#include "fault_reader.hpp"
#include "mesh_import.hpp"
#include "motion_reader.hpp"
#include "pose_reader.hpp"
#include "scanner_reader.hpp"
#include "scanners_reader.hpp"
#include "yaml_fields.hpp"
#include "yaml_precount.hpp"

#include "ldoem/base/regular_file.hpp"

#include <array>
#include <cerrno>
#include <cstring>
#include <istream>
#include <map>
#include <streambuf>
#include <utility>

namespace ldoem::scene {
namespace {

using detail::Constraint;
using detail::fail;
using detail::MapReader;

constexpr std::array<std::string_view, kEffectCount> kEffectNames{
    "noise", "intensity", "incidence", "mixed_pixels",
    "motor_dynamics", "head_dynamics", "sweep_motion", "bus_timing",
    "waveform", "snr_noise", "atmosphere",
};

constexpr std::array<std::string_view, 6> kShapeKeys{"box", "sphere", "cylinder", "capsule", "plane", "mesh"};

struct LoadContext {
  std::string file;                   // display name, for messages
  std::filesystem::path mesh_folder;  // meshes are relative to this
  // Totals so far, checked against kMaxSceneTriangles and kMaxSceneVertices: a YAML alias that
  // repeats a mesh object repeats its triangles too.
  std::size_t triangles = 0;
  std::size_t vertices = 0;
  std::size_t waypoints = 0;  // all objects' together, checked against kMaxSceneWaypoints
  // Each (file, scale) is imported once per scene, however often aliases repeat it.
  std::map<std::pair<std::string, std::array<double, 3>>, Mesh> imported;
};

Shape read_box(const std::string& file, MapReader& map) {
  Box box;
  box.size_m = detail::read_vector3(file, map.require("size_m"), map.child_path("size_m"), Constraint::positive);
  return box;
}

Shape read_sphere(MapReader& map) {
  Sphere sphere{};
  sphere.radius_m = detail::read_double(map.file(), map.require("radius_m"), map.child_path("radius_m"),
                                        Constraint::positive);
  return sphere;
}

// ODE conventions: a cylinder's length is its full height; a capsule's is the length of its
// cylindrical part, without the two hemispherical caps (so 0 makes a sphere).
template <class Round>
Shape read_round(MapReader& map, Constraint length_constraint) {
  Round shape{};
  shape.radius_m = detail::read_double(map.file(), map.require("radius_m"), map.child_path("radius_m"),
                                       Constraint::positive);
  shape.length_m = detail::read_double(map.file(), map.require("length_m"), map.child_path("length_m"),
                                       length_constraint);
  return shape;
}

Shape read_plane(MapReader& map) {
  Plane plane{};
  const YAML::Node normal_node = map.require("normal");
  const Eigen::Vector3d normal = detail::read_vector3(map.file(), normal_node, map.child_path("normal"));
  if (!(normal.norm() > 1e-9)) {
    fail(map.file(), SceneErrorKind::out_of_range, normal_node, map.child_path("normal"), "must not be zero");
  }
  plane.normal = normal.normalized();
  plane.offset_m = 0.0;
  detail::read_field(map, "offset_m", plane.offset_m);
  return plane;
}

Shape read_mesh(LoadContext& context, MapReader& map) {
  Mesh mesh;
  const YAML::Node file_node = map.require("file");
  mesh.path = detail::read_string(map.file(), file_node, map.child_path("file"));
  if (auto scale = map.get("scale")) {
    if (scale->IsSequence()) {
      mesh.scale = detail::read_vector3(map.file(), *scale, map.child_path("scale"), Constraint::positive);
    } else {
      mesh.scale.setConstant(detail::read_double(map.file(), *scale, map.child_path("scale"), Constraint::positive));
    }
  }
  const std::filesystem::path resolved = context.mesh_folder / mesh.path;
  const auto key = std::make_pair(resolved.lexically_normal().string(),
                                  std::array<double, 3>{mesh.scale.x(), mesh.scale.y(), mesh.scale.z()});
  if (const auto found = context.imported.find(key); found != context.imported.end()) {
    Mesh copy = found->second;
    copy.path = mesh.path;
    mesh = std::move(copy);
  } else {
    if (auto problem = detail::import_mesh(resolved, mesh, kMaxSceneTriangles - context.triangles,
                                           kMaxSceneVertices - context.vertices)) {
      fail(map.file(), SceneErrorKind::mesh, file_node, map.child_path("file"), *problem);
    }
    context.imported.emplace(key, mesh);
  }
  if (mesh.triangles.size() > kMaxSceneTriangles - context.triangles ||
      mesh.vertices_m.size() > kMaxSceneVertices - context.vertices) {
    fail(map.file(), SceneErrorKind::out_of_range, file_node, map.child_path("file"),
         "the scene would have more than " + std::to_string(kMaxSceneTriangles) + " triangles or " +
             std::to_string(kMaxSceneVertices) + " vertices");
  }
  context.triangles += mesh.triangles.size();
  context.vertices += mesh.vertices_m.size();
  return mesh;
}

Shape read_shape(LoadContext& context, std::string_view kind, const YAML::Node& node,
                 const std::string& path) {
  MapReader map(context.file, node, path);
  Shape shape;
  if (kind == "box") shape = read_box(context.file, map);
  if (kind == "sphere") shape = read_sphere(map);
  if (kind == "cylinder") shape = read_round<Cylinder>(map, Constraint::positive);
  if (kind == "capsule") shape = read_round<Capsule>(map, Constraint::non_negative);
  if (kind == "plane") shape = read_plane(map);
  if (kind == "mesh") shape = read_mesh(context, map);
  map.finish();
  return shape;
}

// D12: `motion` or `dynamics`, checked against the object's shape and pose.
void read_object_motion(LoadContext& context, MapReader& map, std::string_view shape_key, SceneObject& object) {
  if (map.has("motion") && map.has("dynamics")) {
    fail(context.file, SceneErrorKind::conflicting_keys, map.node(), map.child_path("dynamics"),
         "an object moves by motion or by dynamics, not both");
  }
  for (std::string_view key : {"motion", "dynamics"}) {
    if (map.has(key) && shape_key == "plane") {
      fail(context.file, SceneErrorKind::conflicting_keys, *map.get(key), map.child_path(key),
           "planes are unbounded and cannot move");
    }
  }
  if (auto motion = map.get("motion")) {
    object.motion = detail::read_motion(context.file, *motion, map.child_path("motion"));
    if (const auto* path = std::get_if<Waypoints>(&*object.motion)) {
      context.waypoints += path->points.size();
      if (context.waypoints > kMaxSceneWaypoints) {
        fail(context.file, SceneErrorKind::out_of_range, *motion, map.child_path("motion"),
             "the scene would have more than " + std::to_string(kMaxSceneWaypoints) + " waypoints in all");
      }
    }
    if (std::holds_alternative<Waypoints>(*object.motion) && map.has("pose")) {
      fail(context.file, SceneErrorKind::conflicting_keys, *map.get("pose"), map.child_path("pose"),
           "waypoints give absolute poses; drop pose or use velocities");
    }
    if (std::holds_alternative<Waypoints>(*object.motion)) {
      object.pose = pose_at(*object.motion, object.pose, 0.0);
    }
  }
  if (auto dynamics = map.get("dynamics")) {
    if (shape_key == "mesh") {
      fail(context.file, SceneErrorKind::conflicting_keys, *dynamics, map.child_path("dynamics"),
           "dynamics bodies are boxes, spheres, cylinders or capsules (a mesh has no ODE inertia here)");
    }
    object.dynamics = detail::read_dynamics(context.file, *dynamics, map.child_path("dynamics"));
  }
}

SceneObject read_object(LoadContext& context, const YAML::Node& node, std::size_t index) {
  const std::string path = "objects[" + std::to_string(index) + "]";
  MapReader map(context.file, node, path);
  SceneObject object;
  object.name = "object" + std::to_string(index);
  detail::read_field(map, "name", object.name);
  detail::read_field(map, "reflectance", object.reflectance, Constraint::unit_interval);
  detail::read_field(map, "retroreflective", object.retroreflective);

  std::string_view shape_key;
  for (std::string_view key : kShapeKeys) {
    if (!map.has(key)) continue;
    if (!shape_key.empty()) {
      fail(context.file, SceneErrorKind::conflicting_keys, node, map.child_path(key),
           "an object has exactly one shape (also given: " + std::string(shape_key) + ")");
    }
    shape_key = key;
  }
  if (shape_key.empty()) {
    fail(context.file, SceneErrorKind::missing_key, node, path,
         "needs one shape key: box, sphere, cylinder, capsule, plane or mesh");
  }
  object.shape = read_shape(context, shape_key, *map.get(shape_key), map.child_path(shape_key));

  if (auto pose = map.get("pose")) {
    if (shape_key == "plane") {
      fail(context.file, SceneErrorKind::conflicting_keys, *pose, map.child_path("pose"),
           "planes are not placeable (ODE); use plane.normal and plane.offset_m");
    }
    object.pose = detail::read_pose(context.file, *pose, map.child_path("pose"));
  }
  read_object_motion(context, map, shape_key, object);
  map.finish();
  return object;
}

// Effects that only make sense together: a combination that would silently do nothing, or two
// that model the same thing, is a located error.
void check_effect_combinations(const std::string& file, const YAML::Node& node, const std::string& path,
                               const EffectSet& effects) {
  const auto position_of = [&](Effect effect) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      if (node[i].IsScalar() && node[i].Scalar() == effect_name(effect)) return i;
    }
    return std::size_t{0};
  };
  const bool uses_irradiance = effects.has(Effect::intensity) || effects.has(Effect::mixed_pixels) ||
                               effects.has(Effect::waveform) || effects.has(Effect::snr_noise);
  if (effects.has(Effect::incidence) && !uses_irradiance) {
    const std::size_t i = position_of(Effect::incidence);
    fail(file, SceneErrorKind::conflicting_keys, node[i], path + "[" + std::to_string(i) + "]",
         "incidence scales the received power, so alone it changes nothing: name intensity too "
         "(or mixed_pixels, waveform or snr_noise)");
  }
  if (effects.has(Effect::atmosphere) && !uses_irradiance) {
    const std::size_t i = position_of(Effect::atmosphere);
    fail(file, SceneErrorKind::conflicting_keys, node[i], path + "[" + std::to_string(i) + "]",
         "atmosphere attenuates the received power, so alone it changes nothing: name intensity too "
         "(or mixed_pixels, waveform or snr_noise)");
  }
  if (effects.has(Effect::noise) && effects.has(Effect::snr_noise)) {
    const std::size_t i = position_of(Effect::snr_noise);
    fail(file, SceneErrorKind::conflicting_keys, node[i], path + "[" + std::to_string(i) + "]",
         "snr_noise already adds noise's constant sigma (as its floor): name one of noise and snr_noise");
  }
}

EffectSet read_effects_at(const std::string& file, const YAML::Node& node, const std::string& path) {
  detail::require_sequence(file, node, path);
  EffectSet effects;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string item_path = path + "[" + std::to_string(i) + "]";
    const std::string name = detail::read_string(file, node[i], item_path);
    bool known = false;
    for (std::size_t e = 0; e < kEffectNames.size(); ++e) {
      if (name != kEffectNames[e]) continue;
      const auto effect = static_cast<Effect>(e);
      if (effects.has(effect)) fail(file, SceneErrorKind::duplicate_key, node[i], item_path, "effect named twice");
      effects.add(effect);
      known = true;
    }
    if (!known) {
      fail(file, SceneErrorKind::unknown_effect, node[i], item_path,
           "unknown effect '" + name + "' (D9: noise, intensity, incidence, mixed_pixels, "
           "motor_dynamics, head_dynamics, sweep_motion, bus_timing; D13: waveform, snr_noise, "
           "atmosphere)");
    }
  }
  check_effect_combinations(file, node, path, effects);
  return effects;
}

Scene read_scene(LoadContext& context, const YAML::Node& root) {
  MapReader map(context.file, root, "");
  Scene scene;
  scene.source_path = context.file;
  detail::read_field(map, "seed", scene.seed, 0, UINT64_MAX);
  std::string description;  // free text for people; not used by the emulator
  detail::read_field(map, "description", description);
  if (auto effects = map.get("effects")) scene.effects = read_effects_at(context.file, *effects, "effects");
  // D3 calls the section `device`, the issue `scanner`: both spellings, never both at once.
  if (map.has("scanner") && map.has("device")) {
    fail(context.file, SceneErrorKind::conflicting_keys, root, "device", "give either scanner or device, not both");
  }
  for (std::string_view key : {"scanner", "device"}) {
    if (auto section = map.get(key)) {
      scene.scanner = detail::read_scanner(context.file, *section, std::string(key));
      detail::check_fog_returns(context.file, *section, std::string(key), scene.scanner, scene.effects);
    }
  }
  // Issue 15: several scanners, each a `scanner:` section with a name and its endpoints.
  if (auto list = map.get("scanners")) {
    for (std::string_view key : {"scanner", "device"}) {
      if (map.has(key)) {
        fail(context.file, SceneErrorKind::conflicting_keys, *list, "scanners",
             "give either scanners or " + std::string(key) + ", not both");
      }
    }
    scene.scanners = detail::read_scanners(context.file, *list, scene.effects);
    scene.scanner = scene.scanners.front().config;
    scene.effects = scene.scanners.front().effects;
  }
  if (auto world = map.get("world")) scene.world = detail::read_world(context.file, *world, "world");
  if (auto faults = map.get("faults")) scene.faults = detail::read_faults(context.file, *faults);
  if (auto objects = map.get("objects")) {
    detail::require_sequence(context.file, *objects, "objects");
    if (objects->size() > kMaxSceneObjects) {
      fail(context.file, SceneErrorKind::out_of_range, *objects, "objects",
           "more than " + std::to_string(kMaxSceneObjects) + " objects");
    }
    for (std::size_t i = 0; i < objects->size(); ++i) {
      scene.objects.push_back(read_object(context, (*objects)[i], i));
    }
  }
  map.finish();
  return scene;
}

// The text as an istream without a copy (YAML::Load(std::string) copies it into a stringstream).
class TextBuffer : public std::streambuf {
 public:
  explicit TextBuffer(std::string_view text) {
    char* begin = const_cast<char*>(text.data());  // read only: get area, no put area
    setg(begin, begin, begin + text.size());
  }
};

SceneError whole_file_error(std::string file, SceneErrorKind kind, std::string detail) {
  SceneError error;
  error.kind = kind;
  error.file = std::move(file);
  error.detail = std::move(detail);
  return error;
}

}  // namespace

namespace detail {
EffectSet read_effects(const std::string& file, const YAML::Node& node, const std::string& path) {
  return read_effects_at(file, node, path);
}
}  // namespace detail

std::string SceneError::message() const {
  // Appended piece by piece: g++ 12 at -O3 warns (-Wrestrict) on `text += ":" + ...` here.
  std::string text = file;
  if (line > 0) {
    text.append(":").append(std::to_string(line)).append(":").append(std::to_string(column));
  }
  text.append(": ");
  if (!key_path.empty()) text.append(key_path).append(": ");
  text.append(detail);
  return text;
}

std::string_view to_string(SceneErrorKind kind) {
  switch (kind) {
    case SceneErrorKind::io: return "io";
    case SceneErrorKind::syntax: return "syntax";
    case SceneErrorKind::unknown_key: return "unknown_key";
    case SceneErrorKind::duplicate_key: return "duplicate_key";
    case SceneErrorKind::missing_key: return "missing_key";
    case SceneErrorKind::conflicting_keys: return "conflicting_keys";
    case SceneErrorKind::wrong_type: return "wrong_type";
    case SceneErrorKind::not_finite: return "not_finite";
    case SceneErrorKind::out_of_range: return "out_of_range";
    case SceneErrorKind::mesh: return "mesh";
    case SceneErrorKind::unknown_effect: return "unknown_effect";
    case SceneErrorKind::unknown_fault: return "unknown_fault";
    case SceneErrorKind::unknown_service: return "unknown_service";
    case SceneErrorKind::internal: return "internal";
  }
  return "internal";
}

std::string_view effect_name(Effect effect) { return kEffectNames.at(static_cast<std::size_t>(effect)); }

SceneResult load_scene_from_string(std::string_view yaml, std::string_view display_name) {
  LoadContext context;
  context.file = std::string(display_name);
  context.mesh_folder = std::filesystem::path(display_name).parent_path();
  try {
    detail::precount_yaml(yaml, context.file);  // the limits before the node tree's memory
    TextBuffer buffer(yaml);
    std::istream in(&buffer);
    const YAML::Node root = YAML::Load(in);
    if (!root.IsDefined() || root.IsNull()) {
      return base::Unexpected(whole_file_error(context.file, SceneErrorKind::wrong_type, "empty scene: expected a map"));
    }
    return read_scene(context, root);
  } catch (const detail::LoadFailure& failure) {
    return base::Unexpected(failure.error);
  } catch (const YAML::Exception& yaml_error) {
    SceneError error = whole_file_error(context.file, SceneErrorKind::syntax, yaml_error.msg);
    if (yaml_error.mark.line >= 0) {
      error.line = yaml_error.mark.line + 1;
      error.column = yaml_error.mark.column + 1;
    }
    return base::Unexpected(std::move(error));
  } catch (const std::exception& other) {
    return base::Unexpected(whole_file_error(context.file, SceneErrorKind::internal, other.what()));
  }
}

SceneResult load_scene(const std::filesystem::path& path) {
  // Issue 27 (D7): a FIFO, /dev/zero or a folder is refused at once; the 64 MiB bound counts the
  // bytes read, not st_size (0 for /dev/zero).
  auto text = base::read_regular_file(path, kMaxSceneFileBytes);
  if (!text) {
    const int error_number = text.error().error_number;
    std::string detail = text.error().text;  // "is a FIFO, not a regular file"
    if (error_number == EFBIG) detail = "scene file larger than " + std::to_string(kMaxSceneFileBytes >> 20) + " MiB";
    if (detail.rfind("cannot open", 0) == 0) detail = "cannot open scene file: " + std::string(std::strerror(error_number));
    return base::Unexpected(whole_file_error(path.string(), SceneErrorKind::io, detail));
  }
  return load_scene_from_string(*text, path.string());
}

}  // namespace ldoem::scene
