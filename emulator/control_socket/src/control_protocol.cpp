#include "ldoem/control_socket/control_protocol.hpp"

#include <cmath>

namespace ldoem::control_socket {
namespace {

using nlohmann::json;

std::string dump(const json& value) {
  // Invalid UTF-8 in echoed text (an id, an unknown command name) is replaced, never thrown on.
  return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string reply(json body, const json* id) {
  if (id) body["id"] = *id;
  return dump(body);
}

std::string result_line(const CommandResult& result, const json* id) {
  if (const auto* error = std::get_if<CommandError>(&result)) return error_line(error->error_class, error->desc, id);
  return reply(json{{"return", std::get<json>(result)}}, id);
}

std::optional<std::string> no_arguments(const json& arguments, std::string_view command) {
  if (!arguments.empty()) return std::string(command) + " takes no arguments";
  return std::nullopt;
}

std::string field_error_text(const faults::FieldError& error) {
  return error.key.empty() ? error.detail : error.key + ": " + error.detail;
}

}  // namespace

const std::vector<CommandInfo>& command_table() {
  // inject-fault's arguments are a fault entry's fields (faults::FaultEntryBuilder, with `on` and
  // `every` as maps) plus "scanner".
  static const std::vector<CommandInfo> table{
      {"qmp_capabilities", {}},
      {"inject-fault", {"kind", "at_s", "on", "every", "probability", "duration_s", "count", "transport", "service",
                        "from_deg", "to_deg", "fraction", "delay_s", "bytes_kept", "bytes", "bytes_per_s", "off_s",
                        "scanner"}},
      {"clear-fault", {"id", "scanner"}},
      {"query-faults", {"scanner"}},
      {"query-status", {"scanner"}},
      {"power-cycle", {"off_s", "scanner"}},
      {"move-object", {"name", "position_m", "rpy_deg", "at_s", "keep_velocity"}},
      {"add-object", {"object", "at_s"}},
      {"remove-object", {"name", "at_s"}},
      {"query-commands", {}},
      {"quit", {}}};
  return table;
}

const std::vector<std::string>& command_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const CommandInfo& command : command_table()) out.push_back(command.name);
    return out;
  }();
  return names;
}

std::string greeting_line(std::string_view version) {
  return dump(json{{"QMP",
                    {{"version", {{"package", "ldoem-emud"}, {"ldoem", std::string(version)}}},
                     {"capabilities", json::array({"faults", "events"})},
                     {"commands", command_names()}}}});
}

std::string error_line(std::string_view error_class, std::string_view desc, const json* id) {
  return reply(json{{"error", {{"class", std::string(error_class)}, {"desc", std::string(desc)}}}}, id);
}

std::string event_line(std::string_view event, const json& data, faults::SimTime at) {
  const auto micros = std::chrono::duration_cast<std::chrono::microseconds>(at).count();
  return dump(json{{"event", std::string(event)},
                   {"data", data},
                   {"timestamp", {{"seconds", micros / 1'000'000}, {"microseconds", micros % 1'000'000}}}});
}

std::variant<faults::FaultSpec, faults::FieldError> fault_from_json(const json& arguments) {
  faults::FaultEntryBuilder builder;
  auto value_of = [](const std::string& key, const json& value) -> std::variant<faults::FieldValue, faults::FieldError> {
    if (value.is_number()) return faults::FieldValue{value.get<double>()};
    if (value.is_string()) return faults::FieldValue{value.get<std::string>()};
    return faults::FieldError{faults::FieldErrorKind::wrong_type, key, "must be a number or a text"};
  };
  auto apply = [&](const std::string& key, const json& value) -> std::optional<faults::FieldError> {
    auto field = value_of(key, value);
    if (auto* problem = std::get_if<faults::FieldError>(&field)) return *problem;
    return builder.set(key, std::get<faults::FieldValue>(field));
  };
  if (!arguments.is_object()) return faults::FieldError{faults::FieldErrorKind::wrong_type, "", "arguments must be an object"};
  for (const auto& [key, value] : arguments.items()) {
    if (faults::FaultEntryBuilder::is_trigger_map(key)) {
      if (!value.is_object()) return faults::FieldError{faults::FieldErrorKind::wrong_type, key, "must be an object"};
      for (const auto& [member, member_value] : value.items()) {
        if (auto problem = apply(key + "." + member, member_value)) return *problem;
      }
    } else if (auto problem = apply(key, value)) {
      return *problem;
    }
  }
  auto finished = builder.finish();
  if (auto* problem = std::get_if<faults::FieldError>(&finished)) return *problem;
  return std::get<faults::FaultSpec>(finished);
}

std::string handle_line(std::string_view line, ControlTarget& target) {
  json request = json::parse(line.begin(), line.end(), nullptr, false);
  if (request.is_discarded()) return error_line(kGenericError, "not a JSON value");
  if (!request.is_object()) return error_line(kGenericError, "a request is a JSON object");
  const json* id = request.contains("id") ? &request["id"] : nullptr;
  if (!request.contains("execute") || !request["execute"].is_string()) {
    return error_line(kGenericError, "a request needs \"execute\": a command name", id);
  }
  for (const auto& [key, value] : request.items()) {
    if (key != "execute" && key != "arguments" && key != "id") {
      return error_line(kGenericError, "unknown request member '" + key + "'", id);
    }
  }
  const std::string command = request["execute"].get<std::string>();
  json arguments = json::object();
  if (request.contains("arguments")) {
    if (!request["arguments"].is_object()) return error_line(kGenericError, "\"arguments\" must be an object", id);
    arguments = request["arguments"];
  }
  try {
    if (command == "qmp_capabilities") return reply(json{{"return", json::object()}}, id);
    if (command == "query-commands") {
      if (auto problem = no_arguments(arguments, command)) return error_line(kGenericError, *problem, id);
      json commands = json::array();
      for (const CommandInfo& info : command_table()) commands.push_back({{"name", info.name}, {"arguments", info.arguments}});
      return reply(json{{"return", commands}}, id);
    }
    // The fault commands act on one scanner: "scanner" names it, else the daemon's first.
    ControlTarget* chosen = &target;
    const bool per_scanner = command == "inject-fault" || command == "power-cycle" || command == "clear-fault" ||
                             command == "query-faults" || command == "query-status";
    if (per_scanner && arguments.contains("scanner")) {
      if (!arguments["scanner"].is_string()) return error_line(kGenericError, "scanner: must be a scanner's name", id);
      const std::string name = arguments["scanner"].get<std::string>();
      chosen = target.scanner(name);
      if (chosen == nullptr) return error_line(kGenericError, "scanner: no scanner named '" + name + "'", id);
      arguments.erase("scanner");
    }
    ControlTarget& target_of_command = *chosen;
    if (command == "inject-fault" || command == "power-cycle") {
      if (command == "power-cycle") {
        for (const auto& [key, value] : arguments.items()) {
          if (key != "off_s") return error_line(kGenericError, "power-cycle takes only off_s", id);
        }
        arguments["kind"] = "power_cycle";
      }
      auto spec = fault_from_json(arguments);
      if (auto* problem = std::get_if<faults::FieldError>(&spec)) {
        return error_line(kGenericError, field_error_text(*problem), id);
      }
      return result_line(target_of_command.inject_fault(std::get<faults::FaultSpec>(spec)), id);
    }
    if (command == "clear-fault") {
      std::optional<std::uint64_t> fault_id;
      for (const auto& [key, value] : arguments.items()) {
        if (key != "id") return error_line(kGenericError, "clear-fault takes only id", id);
        if (!value.is_number_unsigned()) return error_line(kGenericError, "id: must be a fault id (query-faults)", id);
        fault_id = value.get<std::uint64_t>();
      }
      return result_line(target_of_command.clear_fault(fault_id), id);
    }
    if (command == "query-faults" || command == "query-status" || command == "quit") {
      if (auto problem = no_arguments(arguments, command)) return error_line(kGenericError, *problem, id);
      if (command == "query-faults") return reply(json{{"return", target_of_command.query_faults()}}, id);
      if (command == "query-status") return reply(json{{"return", target_of_command.query_status()}}, id);
      target.quit();
      return reply(json{{"return", json::object()}}, id);
    }
    if (command == "move-object") return result_line(target.move_object(arguments), id);
    if (command == "add-object") {
      const std::optional<json> kept_id = id ? std::optional<json>(*id) : std::nullopt;
      const auto reply_line = [kept_id](const CommandResult& result) {
        return result_line(result, kept_id ? &*kept_id : nullptr);
      };
      if (target.add_object_later(arguments, reply_line)) return std::string();  // answered later
      return result_line(target.add_object(arguments), id);
    }
    if (command == "remove-object") return result_line(target.remove_object(arguments), id);
  } catch (const json::exception& failure) {
    return error_line(kGenericError, failure.what(), id);
  }
  return error_line(kCommandNotFound, "The command " + command + " has not been found", id);
}

}  // namespace ldoem::control_socket
