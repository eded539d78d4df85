#include "ldoem/control_socket/command_table.hpp"

#include <utility>

namespace ldoem::control_socket {
namespace {

using nlohmann::json;
using Type = ArgumentType;

const ArgumentSpec kScanner{"scanner", Type::text, false, "a scanner's name"};

std::vector<CommandSpec> make_table() {
  // inject-fault's arguments are a fault entry's fields (faults::FaultEntryBuilder, with `on` and
  // `every` as maps); their values are checked by that grammar, their types here.
  std::vector<ArgumentSpec> fault_fields{
      {"kind", Type::text, true, "a D11 fault name (motor_stall, drop_reply, ...)"},
      {"at_s", Type::number, false, ""},
      {"on", Type::object, false, "an object {\"service\": NAME, \"nth\": N}"},
      {"every", Type::object, false, "an object {\"service\": NAME, \"count\": N}"},
      {"probability", Type::number, false, ""},
      {"duration_s", Type::number, false, ""},
      {"count", Type::number, false, ""},
      {"transport", Type::text, false, "tcp, serial, can, lpt or any"},
      {"service", Type::text, false, "a service name (GET_STATUS, ...)"},
      {"from_deg", Type::number, false, ""},
      {"to_deg", Type::number, false, ""},
      {"fraction", Type::number, false, ""},
      {"delay_s", Type::number, false, ""},
      {"bytes_kept", Type::number, false, ""},
      {"bytes", Type::number, false, ""},
      {"bytes_per_s", Type::number, false, ""},
      {"off_s", Type::number, false, ""},
  };
  const ArgumentSpec at_s{"at_s", Type::number, false, "a device time in seconds"};
  const ArgumentSpec object_name{"name", Type::text, true, "an object's name"};
  return {
      {"qmp_capabilities", "QMP's capability negotiation: accepted, optional, does nothing", {}, false},
      {"inject-fault", "inject a D11 fault (a fault entry, docs/faults.md); no trigger means now", fault_fields, true},
      {"clear-fault", "clear one fault by its id, or every fault without one",
       {{"id", Type::count, false, "a fault id (query-faults)"}}, true},
      {"query-faults", "list the active faults", {}, true},
      {"query-status", "state, power, head speed, tilt steps, active faults and counters", {}, true},
      {"power-cycle", "cut the power for off_s seconds (default 1), then restore it",
       {{"off_s", Type::number, false, ""}}, true},
      {"move-object", "put a scene object at a new pose, now or at device time at_s (D12)",
       {object_name,
        {"position_m", Type::list, true, "a list of three numbers (metres)"},
        {"rpy_deg", Type::list, false, "a list of three numbers (degrees)"},
        at_s,
        {"keep_velocity", Type::boolean, false, ""}},
       false},
      {"add-object", "add an object (one entry of a scene's objects list), now or at at_s (D12)",
       {{"object", Type::object, true, "one entry of a scene's objects list (docs/scenes.md)"}, at_s}, false},
      {"remove-object", "remove an object (from the scene or added), now or at at_s (D12)", {object_name, at_s}, false},
      {"query-commands", "this table: each command's name, help, arguments and their schema", {}, false},
      {"quit", "stop the daemon after this reply", {}, false},
  };
}

bool has_type(const json& value, ArgumentType type) {
  switch (type) {
    case Type::text: return value.is_string();
    case Type::number: return value.is_number();
    case Type::count: return value.is_number_unsigned();
    case Type::boolean: return value.is_boolean();
    case Type::object: return value.is_object();
    case Type::list: return value.is_array();
  }
  return false;
}

std::string what_of(const ArgumentSpec& argument) {
  if (!argument.what.empty()) return argument.what;
  switch (argument.type) {
    case Type::text: return "a text";
    case Type::number: return "a number";
    case Type::count: return "a whole number >= 0";
    case Type::boolean: return "true or false";
    case Type::object: return "an object";
    case Type::list: return "a list";
  }
  return "a JSON value";
}

// The entry's arguments with "scanner" last for a per-scanner command.
std::vector<ArgumentSpec> all_arguments(const CommandSpec& command) {
  std::vector<ArgumentSpec> out = command.arguments;
  if (command.per_scanner) out.push_back(kScanner);
  return out;
}

// "(quit takes no arguments)", "(query-faults takes no arguments but scanner)",
// "(power-cycle takes off_s, scanner)".
std::string what_it_takes(const CommandSpec& command) {
  std::string names;
  for (const ArgumentSpec& argument : command.arguments) names += (names.empty() ? "" : ", ") + argument.name;
  if (names.empty()) return command.name + " takes no arguments" + (command.per_scanner ? " but scanner" : "");
  return command.name + " takes " + names + (command.per_scanner ? ", scanner" : "");
}

}  // namespace

std::string_view json_type_name(ArgumentType type) {
  switch (type) {
    case Type::text: return "string";
    case Type::number: return "number";
    case Type::count: return "integer";
    case Type::boolean: return "boolean";
    case Type::object: return "object";
    case Type::list: return "array";
  }
  return "";
}

std::vector<std::string> CommandSpec::argument_names() const {
  std::vector<std::string> names;
  for (const ArgumentSpec& argument : all_arguments(*this)) names.push_back(argument.name);
  return names;
}

json CommandSpec::schema() const {
  json out = json::object();
  for (const ArgumentSpec& argument : all_arguments(*this)) {
    json entry{{"type", std::string(json_type_name(argument.type))}, {"required", argument.required}};
    if (!argument.what.empty()) entry["description"] = argument.what;
    out[argument.name] = std::move(entry);
  }
  return out;
}

const std::vector<CommandSpec>& command_table() {
  static const std::vector<CommandSpec> table = make_table();
  return table;
}

const CommandSpec* find_command(std::string_view name) {
  for (const CommandSpec& command : command_table()) {
    if (command.name == name) return &command;
  }
  return nullptr;
}

json describe_commands() {
  json commands = json::array();
  for (const CommandSpec& command : command_table()) {
    commands.push_back({{"name", command.name},
                        {"help", command.help},
                        {"arguments", command.argument_names()},
                        {"schema", command.schema()}});
  }
  return commands;
}

std::optional<std::string> check_arguments(const CommandSpec& command, const json& arguments) {
  const std::vector<ArgumentSpec> known = all_arguments(command);
  for (const auto& [key, value] : arguments.items()) {
    bool found = false;
    for (const ArgumentSpec& argument : known) found = found || argument.name == key;
    if (!found) return command.name + ": unknown argument '" + key + "' (" + what_it_takes(command) + ")";
  }
  for (const ArgumentSpec& argument : known) {
    if (!arguments.contains(argument.name)) {
      if (argument.required) return command.name + ": needs " + argument.name + " (" + what_of(argument) + ")";
    } else if (!has_type(arguments[argument.name], argument.type)) {
      return argument.name + ": must be " + what_of(argument);
    }
  }
  return std::nullopt;
}

}  // namespace ldoem::control_socket
