// ldoem-hub's command line, parsed by a pure function (design.md convention 1).
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/hub/hub_config.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::hub {

// Exit codes (design.md convention 1).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitSignalBase = 128;

struct HubCommandLine {
  bool help = false;
  bool help_all = false;  // --help-all: the full usage text; --help prints the brief one
  bool version = false;  // --version: print base::version_line and exit 0
  std::string config_path;
  std::optional<ListenAddress> listen;               // overrides the file's `listen`
  std::optional<std::chrono::milliseconds> max_age;  // overrides the file's `max_age_ms`
  std::size_t max_clients = 64;
  std::size_t queue_capacity = 256;
  std::size_t max_in_flight = 16;
  std::chrono::milliseconds idle_timeout{60000};
  std::optional<std::string> completion_script;  // --completion bash: print it and exit 0
  bool operator==(const HubCommandLine&) const = default;
};

// `args` without the program name (parsed with CLI11, base/command_line.hpp). The error is one
// line for stderr.
base::Expected<HubCommandLine, std::string> parse_hub_command_line(const std::vector<std::string_view>& args);

std::string hub_usage(std::string_view program);
// What --help prints: a screen of hub_usage (base::brief_help).
std::string hub_brief_usage(std::string_view program);

}  // namespace ldoem::hub
