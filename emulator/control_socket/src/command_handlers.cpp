#include "ldoem/control_socket/command_handlers.hpp"

#include <cstdint>
#include <string>
#include <utility>

#include "ldoem/control_socket/command_table.hpp"

namespace ldoem::control_socket {
namespace {

using nlohmann::json;

std::string field_error_text(const faults::FieldError& error) {
  return error.key.empty() ? error.detail : error.key + ": " + error.detail;
}

// inject-fault and power-cycle: a fault entry through the scene's grammar, then the target.
CommandResult inject(const json& arguments, ControlTarget& target) {
  auto spec = fault_from_json(arguments);
  if (auto* problem = std::get_if<faults::FieldError>(&spec)) {
    return CommandError{std::string(kGenericError), field_error_text(*problem)};
  }
  return target.inject_fault(std::get<faults::FaultSpec>(spec));
}

struct NamedHandler {
  std::string_view name;
  CommandHandler handler;
};

// One handler per entry of command_table.cpp, by name (command_table_test checks both ways).
const NamedHandler kHandlers[] = {
    {"qmp_capabilities", [](const CommandCall&) -> std::optional<CommandResult> { return json::object(); }},
    {"inject-fault",
     [](const CommandCall& call) -> std::optional<CommandResult> { return inject(call.arguments, call.target); }},
    {"clear-fault",
     [](const CommandCall& call) -> std::optional<CommandResult> {
       std::optional<std::uint64_t> id;
       if (call.arguments.contains("id")) id = call.arguments["id"].get<std::uint64_t>();
       return call.target.clear_fault(id);
     }},
    {"query-faults", [](const CommandCall& call) -> std::optional<CommandResult> { return call.target.query_faults(); }},
    {"query-status", [](const CommandCall& call) -> std::optional<CommandResult> { return call.target.query_status(); }},
    {"power-cycle",
     [](const CommandCall& call) -> std::optional<CommandResult> {
       json arguments = call.arguments;
       arguments["kind"] = "power_cycle";
       return inject(arguments, call.target);
     }},
    {"move-object",
     [](const CommandCall& call) -> std::optional<CommandResult> { return call.daemon.move_object(call.arguments); }},
    {"add-object",
     [](const CommandCall& call) -> std::optional<CommandResult> {
       // A mesh import is slow: the target may answer later, off the loop's thread (issue 27).
       if (call.daemon.add_object_later(call.arguments, call.reply_line)) return std::nullopt;
       return call.daemon.add_object(call.arguments);
     }},
    {"remove-object",
     [](const CommandCall& call) -> std::optional<CommandResult> { return call.daemon.remove_object(call.arguments); }},
    {"query-commands", [](const CommandCall&) -> std::optional<CommandResult> { return describe_commands(); }},
    {"quit",
     [](const CommandCall& call) -> std::optional<CommandResult> {
       call.daemon.quit();
       return json::object();
     }},
};

}  // namespace

CommandHandler command_handler(std::string_view name) {
  for (const NamedHandler& entry : kHandlers) {
    if (entry.name == name) return entry.handler;
  }
  return nullptr;
}

}  // namespace ldoem::control_socket
