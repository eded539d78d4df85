// The control socket's commands, each declared once (issue 22): its name, a one-line help, its
// arguments (name, JSON type, required or not) and whether it acts on one scanner. The table is
// declarative (library ldoem_control_commands, no handlers, links only nlohmann_json): the daemon
// checks requests against it and answers query-commands with it (control_protocol.hpp), and
// ldoem-ctl builds its commands and help from it. What each command does is its handler, by the
// same name, in command_handlers.cpp. Adding a command is one entry in commands/command_table.cpp
// and one handler in src/command_handlers.cpp, and their test (plus a ControlTarget method if it
// needs a new action).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace ldoem::control_socket {

// The JSON type an argument must have. `count` is a whole number >= 0 (JSON schema "integer").
enum class ArgumentType { text, number, count, boolean, object, list };

// "string", "number", "integer", "boolean", "object", "array": JSON schema's names.
std::string_view json_type_name(ArgumentType type);

struct ArgumentSpec {
  std::string name;
  ArgumentType type = ArgumentType::number;
  bool required = false;
  // What the value is, for people: "must be <what>" in the error reply and the schema's
  // description. Empty: the type's words ("a number", "a text", ...).
  std::string what;
};

struct CommandSpec {
  std::string name;
  std::string help;                      // one line, for query-commands and people
  std::vector<ArgumentSpec> arguments;   // without "scanner": per_scanner adds it
  bool per_scanner = false;              // takes "scanner": NAME (issue 15)

  // The argument names, "scanner" last for a per-scanner command (query-commands' `arguments`).
  std::vector<std::string> argument_names() const;
  // {"NAME": {"type": "number", "required": false, "description": "..."}, ...}
  nlohmann::json schema() const;
};

const std::vector<CommandSpec>& command_table();

// The entry of that name, or nullptr.
const CommandSpec* find_command(std::string_view name);

// query-commands' answer: for each command its name, help, argument names and schema.
nlohmann::json describe_commands();

// The arguments checked against the entry's schema ("scanner" included for a per-scanner
// command): an unknown argument, a missing required one or one of the wrong type is the reason
// returned (a GenericError's desc). Whether the scanner exists is handle_line's question.
std::optional<std::string> check_arguments(const CommandSpec& command, const nlohmann::json& arguments);

}  // namespace ldoem::control_socket
