// The command line of ldoem-replay, the alias of `ldoem-emud --replay` (docs/replay.md), parsed
// by a pure function on CLI11 (base/command_line.hpp) like the other tools'. Endpoint options are the daemon's, in the
// grammar of docs/endpoints.md: --tcp tcp:HOST[:PORT], --serial serial:pty:PATH,
// --can can:IF[:REQ:RESP], --lpt lpt:pty:PATH | lpt:gpio:CHIP (writes accepted and counted, not
// replayed).
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "ldoem/daemon/options.hpp"
#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/base/expected.hpp"

namespace ldoem::replay {

struct ReplayOptions {
  std::filesystem::path capture;
  daemon::Options endpoints;  // the endpoint fields, log level and timeout
  double speed = 1.0;         // recorded seconds per replayed second
  std::optional<protocol::Transport> transport;  // which recorded transport; default: busiest
  std::optional<std::uint16_t> capture_tcp_port;     // --port: the device's port in the capture; default: detected
  bool help = false;
  bool help_all = false;  // --help-all: the full usage text; --help prints the brief one
  bool version = false;  // --version: print base::version_line and exit 0
  std::optional<std::string> completion_script;  // --completion bash (base/command_line.hpp)
};

struct ReplayUsageError {
  std::string message;
};

[[nodiscard]] base::Expected<ReplayOptions, ReplayUsageError> parse_replay_options(
    std::span<const std::string_view> arguments);

// The daemon's options that serve it: `ldoem-emud --replay CAPTURE` with the same endpoints,
// --time-scale for --speed, --replay-transport and --replay-port.
daemon::Options daemon_options(const ReplayOptions& options);

std::string replay_usage_text();
// What --help prints: a screen of replay_usage_text (base::brief_help).
std::string replay_brief_usage_text();

}  // namespace ldoem::replay
