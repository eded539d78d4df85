// The daemon's fault machinery without I/O (D11). It owns the fault scheduler and acts on the
// control unit: motor faults, spontaneous resets, power cycles and beam faults. The daemon
// feeds it time and requests, performs the control-unit Actions it returns, drops connections
// when it says so, and broadcasts its event lines. Wire faults are read from scheduler() by the
// daemon's wire tap. Deterministic: no clock, no global random state.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ldoem/control/control_unit.hpp"
#include "ldoem/faults/fault_scheduler.hpp"

namespace ldoem::fault_injection {

using faults::SimTime;

// An event for the control socket: name, data, simulated time.
struct InjectorEvent {
  std::string name;  // FAULT_INJECTED, FAULT_CLEARED, POWER_OFF, POWER_ON, STATE_CHANGED
  nlohmann::json data;
  SimTime at{};
};

struct InjectorOutput {
  control::Actions actions;           // perform like any control-unit output
  bool drop_all_connections = false;  // a power cycle began: every host connection goes
  std::vector<InjectorEvent> events;
};

class FaultInjector {
 public:
  // `head_dynamics`: the scene has D9's head_dynamics, so a stall coasts down (D11).
  FaultInjector(std::vector<faults::FaultSpec> scene_faults, std::uint64_t seed, bool head_dynamics,
                control::ControlUnit& unit);

  // Simulated time reached `now`: triggers, expiries, power-on.
  InjectorOutput advance(SimTime now);
  // A request of `service` arrived on `transport` (before the control unit sees it); `seen`: all
  // of it, or the first frame or the rest of a multi-frame ISO-TP request (fault_scheduler.hpp).
  InjectorOutput on_request(SimTime now, std::uint16_t service, faults::Transport transport,
                            faults::RequestSeen seen = faults::RequestSeen::whole);
  // The control socket's inject-fault; `id` is 0 when the entry waits for its trigger.
  InjectorOutput inject(SimTime now, faults::FaultSpec spec, faults::FaultId& id);
  // clear-fault: one (false when no such fault) or all.
  InjectorOutput clear(SimTime now, std::optional<faults::FaultId> id, bool& found);
  // After every control-unit event: a STATE_CHANGED event when the mode changed.
  void note_state(SimTime now, std::vector<InjectorEvent>& events);

  // While off (power_cycle), nothing reaches the device and nothing leaves it.
  bool powered() const { return !power_on_at_; }
  std::optional<SimTime> next_deadline() const;
  nlohmann::json query_faults() const;
  faults::FaultScheduler& scheduler() { return scheduler_; }
  const faults::FaultScheduler& scheduler() const { return scheduler_; }
  // Events the wire tap produced (count used): turned into event lines by the caller.
  void events_from(const std::vector<faults::FaultEvent>& fault_events, InjectorOutput& out);

  std::uint64_t injections() const { return injections_; }

 private:
  void react(const std::vector<faults::FaultEvent>& fault_events, InjectorOutput& out);
  void update_beam_faults();
  void update_motor_fault();

  faults::FaultScheduler scheduler_;
  std::uint64_t seed_;
  bool head_dynamics_;
  control::ControlUnit& unit_;
  std::optional<SimTime> power_on_at_;
  control::DeviceMode last_mode_;
  std::uint64_t injections_ = 0;
};

// JSON of one active fault for query-faults and events.
nlohmann::json fault_json(const faults::ActiveFault& fault);

}  // namespace ldoem::fault_injection
