// The control socket's object commands (D12 runtime changes, docs/faults.md "Control socket"):
// their arguments, checked here without touching the world (the daemon's monitor acts on them:
// monitor/src/object_control.cpp). Pure: JSON in, a request or the reason it is refused out.
// Its own library (ldoem_object_commands): it needs the scene loader, the protocol does not.
//
//   move-object    {"name": "door", "position_m": [x, y, z], "rpy_deg": [r, p, y],
//                   "at_s": 2.5, "keep_velocity": false}
//   add-object     {"object": {<one entry of the scene's objects: list>}, "at_s": 2.5}
//   remove-object  {"name": "crate", "at_s": 2.5}
//
// at_s is device time (the profiles' clock, seconds since power-up); without it, now.
#pragma once

#include "ldoem/base/expected.hpp"
#include <optional>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "ldoem/scene/scene.hpp"

namespace ldoem::control_socket {

struct MoveObjectRequest {
  std::string name;
  scene::Pose pose;
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();  // as given, for the event
  std::optional<double> at_s;
  bool keep_velocity = false;
};

struct AddObjectRequest {
  scene::SceneObject object;  // checked by the scene loader, as in a scene file
  std::optional<double> at_s;
};

struct RemoveObjectRequest {
  std::string name;
  std::optional<double> at_s;
};

base::Expected<MoveObjectRequest, std::string> parse_move_object(const nlohmann::json& arguments);
using ParsedAddObject = base::Expected<AddObjectRequest, std::string>;
ParsedAddObject parse_add_object(const nlohmann::json& arguments);
base::Expected<RemoveObjectRequest, std::string> parse_remove_object(const nlohmann::json& arguments);

// The device time a command acts at: at_s, or `now_s` without it; refused in the past.
base::Expected<double, std::string> command_time(std::optional<double> at_s, double now_s);

}  // namespace ldoem::control_socket
