// ldoem-ctl's command line -> one control request (docs/faults.md). Pure: argv in, a plan out.
// Its commands and their help are the control socket's command table's (command_table.hpp),
// plus events and send.
//
//   ldoem-ctl --control PATH inject-fault motor_stall --duration 2
//   ldoem-ctl --control PATH inject-fault drop_reply --on GET_STATUS:3 --transport tcp
//   ldoem-ctl --control PATH clear-fault [ID]
//   ldoem-ctl --control PATH query-faults | query-status | query-commands | quit
//   ldoem-ctl --control PATH power-cycle [--off 2]
//   ldoem-ctl --control PATH move-object NAME --position x,y,z [--rpy r,p,y] [--at S] [--keep-velocity]
//   ldoem-ctl --control PATH add-object '{"name": "crate", "box": {"size_m": [1, 1, 1]}, ...}' [--at S]
//   ldoem-ctl --control PATH remove-object NAME [--at S]
//   ldoem-ctl --control PATH events [--count N] [--timeout S]
//   ldoem-ctl --control PATH send '{"execute": "query-status"}'
//
// Exit codes: 0 done, 1 the daemon answered an error or could not be reached, 2 usage.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

namespace ldoem::ctl {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

struct CtlPlan {
  std::string control_path;
  bool json_output = false;
  std::chrono::milliseconds timeout{5000};  // for the reply; events: how long to follow (0 = forever)
  // Either a request to send, or follow events.
  std::optional<nlohmann::json> request;
  bool follow_events = false;
  std::optional<std::uint64_t> event_count;  // events: stop after this many
};

struct CtlExit {
  int code = kExitOk;   // kExitOk for --help, kExitUsage for errors
  std::string text;     // the help text or the one-line error
};

std::variant<CtlPlan, CtlExit> parse_ctl_options(const std::vector<std::string>& args);

}  // namespace ldoem::ctl
