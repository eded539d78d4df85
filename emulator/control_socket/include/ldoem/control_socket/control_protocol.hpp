// The control protocol of `ldoem-emud --control PATH`: JSON lines in the shape of QEMU's QMP
// (docs/faults.md). Pure: text in, text out; the socket is control_server.hpp's.
//
//   greeting  {"QMP": {"version": {"package": "ldoem-emud", "ldoem": "0.1.0"}, "capabilities": [...]}}
//   request   {"execute": "inject-fault", "arguments": {"kind": "motor_stall", "duration_s": 2}, "id": 1}
//   success   {"return": {"id": 3}, "id": 1}
//   failure   {"error": {"class": "GenericError", "desc": "..."}, "id": 1}
//   event     {"event": "FAULT_INJECTED", "data": {...}, "timestamp": {"seconds": 2, "microseconds": 0}}
//
// Timestamps are simulated time (D7), not wall time, so that the same scene, seed and
// conversation give the same event log (D11). `id` is echoed as given (any JSON value) and
// left out when the request had none. Unlike QMP, capability negotiation is optional:
// `qmp_capabilities` is accepted and does nothing.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "ldoem/faults/fault_spec.hpp"

namespace ldoem::control_socket {

// QMP's error classes: a bad request or a failed command, and an unknown command.
inline constexpr std::string_view kGenericError = "GenericError";
inline constexpr std::string_view kCommandNotFound = "CommandNotFound";

struct CommandError {
  std::string error_class{kGenericError};
  std::string desc;
};
using CommandResult = std::variant<nlohmann::json, CommandError>;

// What the commands act on: the daemon, or a fake in tests.
class ControlTarget {
 public:
  virtual ~ControlTarget() = default;
  // inject-fault and power-cycle: returns {"id": N} (N = 0 when the entry waits for a trigger).
  virtual CommandResult inject_fault(const faults::FaultSpec& spec) = 0;
  // clear-fault: one fault, or all of them without an id.
  virtual CommandResult clear_fault(std::optional<std::uint64_t> id) = 0;
  virtual nlohmann::json query_faults() = 0;
  virtual nlohmann::json query_status() = 0;
  // move-object, add-object, remove-object (D12 runtime changes; the command table checks their
  // arguments' names and types, the target their values: object_commands.hpp). CommandNotFound
  // for a target without a world.
  virtual CommandResult move_object(const nlohmann::json& arguments) { return no_world("move-object", arguments); }
  virtual CommandResult add_object(const nlohmann::json& arguments) { return no_world("add-object", arguments); }
  virtual CommandResult remove_object(const nlohmann::json& arguments) { return no_world("remove-object", arguments); }
  // Issue 27: an add-object whose object needs slow work (a mesh import) may be answered later,
  // off the loop's thread: the target returns true and, once done, sends reply_line(result)
  // itself (ControlServer::defer/complete). False: handle_line calls add_object() at once.
  using ReplyLine = std::function<std::string(const CommandResult&)>;
  virtual bool add_object_later(const nlohmann::json& /*arguments*/, ReplyLine /*reply_line*/) { return false; }
  // quit: the daemon stops after this reply.
  virtual void quit() = 0;
  // The target of one scanner by its scene name, for the fault commands' "scanner" argument
  // (issue 15: several scanners in one daemon); nullptr when there is no such scanner.
  virtual ControlTarget* scanner(std::string_view /*name*/) { return nullptr; }

 private:
  static CommandResult no_world(std::string_view command, const nlohmann::json& /*arguments*/) {
    return CommandError{std::string(kCommandNotFound), std::string(command) + " needs a scene world (D12)"};
  }
};

// The command names this protocol knows (greeting capabilities and help), in the order of the
// command table (command_table.hpp: each command declared once, with its arguments; its handler in
// command_handlers.hpp).
const std::vector<std::string>& command_names();

std::string greeting_line(std::string_view version);

// One request line (without its newline) -> one reply line (without newline), dispatched through
// the command table; empty when the command answers later (add_object_later). Never throws.
std::string handle_line(std::string_view line, ControlTarget& target);

// inject-fault's arguments -> a fault entry, through the grammar the scene loader uses.
std::variant<faults::FaultSpec, faults::FieldError> fault_from_json(const nlohmann::json& arguments);

std::string error_line(std::string_view error_class, std::string_view desc, const nlohmann::json* id = nullptr);
std::string event_line(std::string_view event, const nlohmann::json& data, faults::SimTime at);

}  // namespace ldoem::control_socket
