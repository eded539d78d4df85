// libFuzzer: one control-socket line -> the argument checks of move-object, add-object and
// remove-object (add-object's object goes through the scene loader). Each must return a request
// or a reason; nothing may throw or crash.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <variant>

#include <nlohmann/json.hpp>

#include "ldoem/control_socket/object_commands.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto* text = reinterpret_cast<const char*>(data);
  const nlohmann::json arguments = nlohmann::json::parse(text, text + size, nullptr, false);
  if (arguments.is_discarded() || !arguments.is_object()) return 0;
  try {
    const auto move = ldoem::control_socket::parse_move_object(arguments);
    if (move && (!move->pose.position_m.allFinite() || move->name.empty())) std::abort();
    (void)ldoem::control_socket::parse_add_object(arguments);
    (void)ldoem::control_socket::parse_remove_object(arguments);
    (void)ldoem::control_socket::command_time(0.5, 1.0);
  } catch (...) {
    std::abort();  // the control socket answers every line; a throw here would be a crash there
  }
  return 0;
}
