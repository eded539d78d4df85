// ldoem-ctl's connection: connect to the control socket, read the greeting, send the request,
// print the reply (or follow events). Every wait is bounded by the plan's timeout.
#pragma once

#include <ostream>
#include <string>

#include "ldoem/ctl/ctl_options.hpp"

namespace ldoem::ctl {

// Runs the plan; returns the exit code (kExitOk, kExitFailure).
int run_ctl(const CtlPlan& plan, std::ostream& out, std::ostream& err);

// One reply or event line for people (without --json): "ok", "fault 3", key: value lines, or
// "error CommandNotFound: ...". Pure, tested.
std::string human_text(const nlohmann::json& line);

}  // namespace ldoem::ctl
