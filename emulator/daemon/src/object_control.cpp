// FaultWiring's D12 commands (move-object, add-object, remove-object) and the CONNECTION events:
// the control socket's side of the world, kept apart from the fault machinery in fault_wiring.cpp.
// Each command runs on the loop's thread, between revolutions, so the casters are never busy.
#include <chrono>

#include "ldoem/daemon/fault_wiring.hpp"
#include "ldoem/control_socket/object_commands.hpp"

namespace ldoem::daemon {

using control_socket::AddObjectRequest;
using control_socket::command_time;
using control_socket::CommandError;
using control_socket::MoveObjectRequest;
using control_socket::parse_add_object;
using control_socket::parse_move_object;
using control_socket::parse_remove_object;
using control_socket::RemoveObjectRequest;
using control_socket::CommandResult;
using nlohmann::json;

namespace {

double seconds(base::SimTime time) { return std::chrono::duration<double>(time).count(); }

CommandError refused(std::string desc) { return CommandError{std::string(control_socket::kGenericError), std::move(desc)}; }

json vector_json(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

// A world change that fails inside Embree or ODE (out of memory) is an error reply, never a
// dead daemon: the control socket answers every line.
template <typename Change>
std::variant<double, std::string> guarded(std::string_view command, Change change) {
  try {
    return change();
  } catch (const std::exception& failure) {
    return std::string(command) + ": " + failure.what();
  }
}

}  // namespace

CommandResult FaultWiring::move_object(const json& arguments) {
  auto parsed = parse_move_object(arguments);
  if (auto* problem = std::get_if<std::string>(&parsed)) return refused(*problem);
  const MoveObjectRequest& request = std::get<MoveObjectRequest>(parsed);
  const base::SimTime now = scheduler_.now();
  auto at_s = command_time(request.at_s, seconds(now));
  if (auto* problem = std::get_if<std::string>(&at_s)) return refused("move-object: " + *problem);
  if (world_ == nullptr) return refused("move-object: this daemon has no scene world");
  auto moved = guarded("move-object", [&] {
    return world_->move_object(request.name, request.pose, std::get<double>(at_s), request.keep_velocity);
  });
  if (auto* problem = std::get_if<std::string>(&moved)) return refused(*problem);
  json data{{"name", request.name},
            {"position_m", vector_json(request.pose.position_m)},
            {"rpy_deg", vector_json(request.rpy_deg)},
            {"at_s", std::get<double>(moved)},
            {"keep_velocity", request.keep_velocity}};
  publish({"OBJECT_MOVED", data, now});
  return json{{"name", request.name}, {"at_s", std::get<double>(moved)}};
}

CommandResult FaultWiring::add_object(const json& arguments) {
  auto parsed = parse_add_object(arguments);
  if (auto* problem = std::get_if<std::string>(&parsed)) return refused(*problem);
  AddObjectRequest& request = std::get<AddObjectRequest>(parsed);
  const base::SimTime now = scheduler_.now();
  auto at_s = command_time(request.at_s, seconds(now));
  if (auto* problem = std::get_if<std::string>(&at_s)) return refused("add-object: " + *problem);
  if (world_ == nullptr) return refused("add-object: this daemon has no scene world");
  const std::string name = request.object.name;
  auto added = guarded("add-object", [&] { return world_->add_object(std::move(request.object), std::get<double>(at_s)); });
  if (auto* problem = std::get_if<std::string>(&added)) return refused(*problem);
  publish({"OBJECT_ADDED", json{{"name", name}, {"at_s", std::get<double>(added)}, {"object", arguments["object"]}}, now});
  return json{{"name", name}, {"at_s", std::get<double>(added)}};
}

CommandResult FaultWiring::remove_object(const json& arguments) {
  auto parsed = parse_remove_object(arguments);
  if (auto* problem = std::get_if<std::string>(&parsed)) return refused(*problem);
  const RemoveObjectRequest& request = std::get<RemoveObjectRequest>(parsed);
  const base::SimTime now = scheduler_.now();
  auto at_s = command_time(request.at_s, seconds(now));
  if (auto* problem = std::get_if<std::string>(&at_s)) return refused("remove-object: " + *problem);
  if (world_ == nullptr) return refused("remove-object: this daemon has no scene world");
  auto removed = guarded("remove-object", [&] { return world_->remove_object(request.name, std::get<double>(at_s)); });
  if (auto* problem = std::get_if<std::string>(&removed)) return refused(*problem);
  publish({"OBJECT_REMOVED", json{{"name", request.name}, {"at_s", std::get<double>(removed)}}, now});
  return json{{"name", request.name}, {"at_s", std::get<double>(removed)}};
}

void FaultWiring::on_connection(bool opened, control::ConnectionId connection, std::string_view peer) {
  const std::string label = control::to_string(connection);  // "tcp#3"
  json data{{"transport", label.substr(0, label.find('#'))}, {"connection", connection.index}};
  if (opened) {
    peers_[connection] = std::string(peer);
    data["peer"] = std::string(peer);
  } else {
    forget_delayed(connection);
    if (const auto known = peers_.find(connection); known != peers_.end()) {
      data["peer"] = known->second;
      peers_.erase(known);
    }
  }
  publish({opened ? "CONNECTION_OPENED" : "CONNECTION_CLOSED", data, scheduler_.now()});
}

}  // namespace ldoem::daemon
