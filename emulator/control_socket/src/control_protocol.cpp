#include "ldoem/control_socket/control_protocol.hpp"

#include "ldoem/control_socket/command_handlers.hpp"
#include "ldoem/control_socket/command_table.hpp"

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

}  // namespace

const std::vector<std::string>& command_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const CommandSpec& command : command_table()) out.push_back(command.name);
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
  json arguments = json::object();
  if (request.contains("arguments")) {
    if (!request["arguments"].is_object()) return error_line(kGenericError, "\"arguments\" must be an object", id);
    arguments = request["arguments"];
  }
  const std::string name = request["execute"].get<std::string>();
  const CommandSpec* command = find_command(name);
  const CommandHandler handler = command != nullptr ? command_handler(name) : nullptr;
  if (handler == nullptr) return error_line(kCommandNotFound, "The command " + name + " has not been found", id);
  try {
    if (auto problem = check_arguments(*command, arguments)) return error_line(kGenericError, *problem, id);
    // A per-scanner command acts on the scanner "scanner" names, else on the daemon's first.
    ControlTarget* chosen = &target;
    if (command->per_scanner && arguments.contains("scanner")) {
      const std::string scanner = arguments["scanner"].get<std::string>();
      chosen = target.scanner(scanner);
      if (chosen == nullptr) return error_line(kGenericError, "scanner: no scanner named '" + scanner + "'", id);
      arguments.erase("scanner");
    }
    const std::optional<json> kept_id = id ? std::optional<json>(*id) : std::nullopt;
    const CommandCall call{arguments, *chosen, target, [kept_id](const CommandResult& result) {
                             return result_line(result, kept_id ? &*kept_id : nullptr);
                           }};
    const std::optional<CommandResult> result = handler(call);
    if (!result) return std::string();  // answered later
    return result_line(*result, id);
  } catch (const json::exception& failure) {
    return error_line(kGenericError, failure.what(), id);
  }
}

}  // namespace ldoem::control_socket
