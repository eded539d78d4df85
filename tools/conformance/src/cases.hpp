// The conformance cases, in the order they run. Names are `<group>/<case>`; the runner prefixes
// the transport (`tcp/vectors/GET_STATUS`).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "ldoem/driver/endpoint.hpp"
#include "session.hpp"

namespace ldoem::conformance {

struct Case {
  std::string name;
  std::function<void(Session&)> run;
  // D-decisions (ours, not SICK's) and emulator defaults cannot be asked of a real LD.
  bool emulator_only = false;
  // Restore the baseline (IDLE, D4 configuration) before running; off only for power-up.
  bool needs_baseline = true;
  // Transports the case applies to; empty = all.
  std::vector<protocol::Transport> transports;

  bool applies_to(protocol::Transport kind, Target target) const;
};

// Group builders, one file each.
void add_power_up_cases(std::vector<Case>& cases);
void add_spin_up_cases(std::vector<Case>& cases);
void add_vector_cases(std::vector<Case>& cases, const VectorTable& vectors);
void add_conversation_cases(std::vector<Case>& cases);
void add_failure_cases(std::vector<Case>& cases);
void add_state_cases(std::vector<Case>& cases);
void add_s1_cases(std::vector<Case>& cases);
void add_timing_cases(std::vector<Case>& cases);

std::vector<Case> all_cases(const VectorTable& vectors);

// "SET_CONFIG global id 1, 10 Hz, 0.5°" -> "SET_CONFIG_global_id_1_10_Hz_0.5deg".
std::string slug(std::string_view text);

}  // namespace ldoem::conformance
