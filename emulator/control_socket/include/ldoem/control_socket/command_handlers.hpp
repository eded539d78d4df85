// What each command of the table (command_table.hpp) does: its handler, found by the command's
// name. Apart from the table so that the table links nothing of the daemon's (ldoem-ctl reads
// it); handle_line (control_protocol.hpp) checks a request against the table, then calls this.
#pragma once

#include <optional>
#include <string_view>

#include <nlohmann/json.hpp>

#include "ldoem/control_socket/control_protocol.hpp"

namespace ldoem::control_socket {

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

// The handler of the table's command `name`; nullptr for a name without one.
CommandHandler command_handler(std::string_view name);

}  // namespace ldoem::control_socket
