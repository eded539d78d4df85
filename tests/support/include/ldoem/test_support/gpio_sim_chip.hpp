// The gpio-sim chip `ldoem-lpt` of D8 for the gpio-labelled tests (the line reader's, the
// daemon's, the LPT wire faults'): its label and sysfs folder, from the variables
// `scripts/uml/run.sh --gpio` exports or from running scripts/uml/gpio-sim-setup.sh now.
#pragma once

#include <optional>
#include <string>

namespace ldoem::test_support {

struct SimChip {
  std::string label;
  std::string sysfs;  // /sys/devices/platform/gpio-sim.N/gpiochipM
};

// The chip, or nothing with `why_not` saying what failed (outside the gpio-sim UML kernel).
std::optional<SimChip> sim_chip(std::string& why_not);

// gpio-sim: the pull is the level an input line reads while nobody drives it.
bool pull_sim_line(const SimChip& chip, int line, bool up);

}  // namespace ldoem::test_support
