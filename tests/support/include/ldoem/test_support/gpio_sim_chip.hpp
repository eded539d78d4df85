// The gpio-sim chip `ldoem-lpt` of D8 for the gpio-labelled tests: its label and sysfs folder,
// from the variables `scripts/uml/run.sh --gpio` exports or from running the setup script now.
#pragma once

#include <optional>
#include <string>

namespace ldoem::daemon::test {

struct SimChip {
  std::string label;
  std::string sysfs;
};

// The chip, or nothing with `why_not` saying what failed (outside the gpio-sim UML kernel).
std::optional<SimChip> sim_chip(std::string& why_not);

// gpio-sim: the pull is the level an input line reads while nobody drives it.
bool pull_sim_line(const SimChip& chip, int line, bool up);

}  // namespace ldoem::daemon::test
