// A ControlTarget that records what it was asked, for the protocol and server tests.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "ldoem/control_socket/control_protocol.hpp"

namespace ldoem::control_socket::test {

class FakeTarget final : public ControlTarget {
 public:
  std::vector<faults::FaultSpec> injected;
  std::vector<std::optional<std::uint64_t>> cleared;
  bool quit_asked = false;

  CommandResult inject_fault(const faults::FaultSpec& spec) override {
    injected.push_back(spec);
    return nlohmann::json{{"id", injected.size()}};
  }
  CommandResult clear_fault(std::optional<std::uint64_t> id) override {
    cleared.push_back(id);
    if (id && *id > injected.size()) return CommandError{"GenericError", "no active fault " + std::to_string(*id)};
    return nlohmann::json::object();
  }
  nlohmann::json query_faults() override { return nlohmann::json::array(); }
  nlohmann::json query_status() override { return {{"state", "IDLE"}}; }
  void quit() override { quit_asked = true; }
  // Issue 15: another scanner of the same daemon, reached by the "scanner" argument.
  FakeTarget* other = nullptr;
  std::string other_name;
  ControlTarget* scanner(std::string_view name) override { return other != nullptr && name == other_name ? other : nullptr; }
};

}  // namespace ldoem::control_socket::test
