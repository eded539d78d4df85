#include "ldoem/control_socket/object_commands.hpp"

#include <cmath>
#include <initializer_list>

#include "ldoem/scene/scene_loader.hpp"

namespace ldoem::control_socket {
namespace {

using nlohmann::json;

// Device times beyond this (about 31 years) are refused: they are typos, and far beyond any run.
constexpr double kMaxCommandTime_s = 1e9;

std::optional<std::string> only_keys(const json& arguments, std::string_view command,
                                     std::initializer_list<std::string_view> allowed) {
  for (const auto& [key, value] : arguments.items()) {
    bool known = false;
    for (const std::string_view name : allowed) known = known || key == name;
    if (!known) return std::string(command) + ": unknown argument '" + key + "'";
  }
  return std::nullopt;
}

base::Expected<Eigen::Vector3d, std::string> vector3(const json& value, std::string_view key) {
  if (!value.is_array() || value.size() != 3) return base::Unexpected<std::string>(std::string(key) + ": must be a list of three numbers");
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    if (!value[i].is_number()) return base::Unexpected<std::string>(std::string(key) + ": must be a list of three numbers");
    out[i] = value[i].get<double>();
    if (!std::isfinite(out[i])) return base::Unexpected<std::string>(std::string(key) + ": must be finite");
  }
  return out;
}

std::optional<std::string> read_name(const json& arguments, std::string_view command, std::string& name) {
  if (!arguments.contains("name")) return std::string(command) + ": needs name (the object's name: in the scene)";
  if (!arguments["name"].is_string() || arguments["name"].get<std::string>().empty()) {
    return std::string(command) + ": name must be a non-empty text";
  }
  name = arguments["name"].get<std::string>();
  return std::nullopt;
}

std::optional<std::string> read_time(const json& arguments, std::string_view command, std::optional<double>& at_s) {
  if (!arguments.contains("at_s")) return std::nullopt;
  const json& value = arguments["at_s"];
  if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0 ||
      value.get<double>() > kMaxCommandTime_s) {
    return std::string(command) + ": at_s must be a device time in seconds, 0 to 1e9";
  }
  at_s = value.get<double>();
  return std::nullopt;
}

}  // namespace

base::Expected<MoveObjectRequest, std::string> parse_move_object(const json& arguments) {
  constexpr std::string_view command = "move-object";
  if (auto problem = only_keys(arguments, command, {"name", "position_m", "rpy_deg", "at_s", "keep_velocity"})) {
    return base::Unexpected<std::string>(*problem);
  }
  MoveObjectRequest request;
  if (auto problem = read_name(arguments, command, request.name)) return base::Unexpected<std::string>(*problem);
  if (!arguments.contains("position_m")) return base::Unexpected<std::string>("move-object: needs position_m [x, y, z]");
  auto position = vector3(arguments["position_m"], "move-object: position_m");
  if (!position) return base::Unexpected<std::string>(position.error());
  request.pose.position_m = *position;
  if (arguments.contains("rpy_deg")) {
    auto rpy = vector3(arguments["rpy_deg"], "move-object: rpy_deg");
    if (!rpy) return base::Unexpected<std::string>(rpy.error());
    request.rpy_deg = *rpy;
    if (request.rpy_deg.cwiseAbs().maxCoeff() > 1e6) return base::Unexpected<std::string>("move-object: rpy_deg beyond 1e6 deg");
  }
  request.pose.orientation = scene::rotation_from_rpy_deg(request.rpy_deg);
  if (auto problem = read_time(arguments, command, request.at_s)) return base::Unexpected<std::string>(*problem);
  if (arguments.contains("keep_velocity")) {
    if (!arguments["keep_velocity"].is_boolean()) return base::Unexpected<std::string>("move-object: keep_velocity must be true or false");
    request.keep_velocity = arguments["keep_velocity"].get<bool>();
  }
  return request;
}

base::Expected<AddObjectRequest, std::string> parse_add_object(const json& arguments) {
  constexpr std::string_view command = "add-object";
  if (auto problem = only_keys(arguments, command, {"object", "at_s"})) return base::Unexpected<std::string>(*problem);
  if (!arguments.contains("object") || !arguments["object"].is_object()) {
    return base::Unexpected<std::string>("add-object: needs object: one entry of a scene's objects list (docs/scenes.md)");
  }
  if (!arguments["object"].contains("name") || !arguments["object"]["name"].is_string()) {
    return base::Unexpected<std::string>("add-object: the object needs a name (for move-object and remove-object)");
  }
  AddObjectRequest request;
  if (auto problem = read_time(arguments, command, request.at_s)) return base::Unexpected<std::string>(*problem);
  // JSON is YAML: the object goes through the scene loader, with its checks and messages.
  const std::string text =
      "objects:\n  - " + arguments["object"].dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
  auto loaded = scene::load_scene_from_string(text, "add-object");
  if (!loaded) {
    std::string where = loaded.error().key_path;
    if (where.rfind("objects[0]", 0) == 0) where = "object" + where.substr(10);
    return base::Unexpected<std::string>("add-object: " + (where.empty() ? std::string() : where + ": ") + loaded.error().detail);
  }
  if (loaded->objects.size() != 1) return base::Unexpected<std::string>("add-object: object must be one object");
  request.object = std::move(loaded->objects.front());
  return request;
}

base::Expected<RemoveObjectRequest, std::string> parse_remove_object(const json& arguments) {
  constexpr std::string_view command = "remove-object";
  if (auto problem = only_keys(arguments, command, {"name", "at_s"})) return base::Unexpected<std::string>(*problem);
  RemoveObjectRequest request;
  if (auto problem = read_name(arguments, command, request.name)) return base::Unexpected<std::string>(*problem);
  if (auto problem = read_time(arguments, command, request.at_s)) return base::Unexpected<std::string>(*problem);
  return request;
}

base::Expected<double, std::string> command_time(std::optional<double> at_s, double now_s) {
  if (!at_s) return now_s;
  if (*at_s < now_s) {
    return base::Unexpected<std::string>("at_s " + std::to_string(*at_s) + " is in the past (device time is now " + std::to_string(now_s) + " s)");
  }
  return *at_s;
}

}  // namespace ldoem::control_socket
