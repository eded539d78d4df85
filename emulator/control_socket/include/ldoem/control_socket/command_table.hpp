// The control socket's commands, each declared once (issue 22): its name, a one-line help, its
// arguments (name, JSON type, required or not), whether it acts on one scanner, and its handler.
// handle_line (control_protocol.hpp) checks a request's arguments against the entry, then calls
// the handler; query-commands answers the table itself. Adding a command is one entry in
// command_table.cpp and its test (plus a ControlTarget method if it needs a new action).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "ldoem/control_socket/control_protocol.hpp"

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

// One request, as the handler sees it: its arguments checked against the schema ("scanner"
// taken out), the target it acts on (the named scanner's for a per-scanner command, else the
// daemon's), and the daemon's target (quit and the object commands act on the daemon).
struct CommandCall {
  const nlohmann::json& arguments;
  ControlTarget& target;
  ControlTarget& daemon;
  // For a command answered later (add-object): the reply line of a result, with the request's id.
  ControlTarget::ReplyLine reply_line;
};

// The handler's answer; std::nullopt when the reply is sent later (ControlTarget::add_object_later).
using CommandHandler = std::optional<CommandResult> (*)(const CommandCall& call);

struct CommandSpec {
  std::string name;
  std::string help;                      // one line, for query-commands and people
  std::vector<ArgumentSpec> arguments;   // without "scanner": per_scanner adds it
  bool per_scanner = false;              // takes "scanner": NAME (issue 15)
  CommandHandler handler = nullptr;

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
