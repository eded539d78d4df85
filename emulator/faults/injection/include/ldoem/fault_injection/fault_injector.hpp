// A device's fault machinery without I/O (D11). It owns the fault scheduler and acts on the
// control unit: motor faults, spontaneous resets, power cycles and beam faults. Its caller, the
// device's FaultTap (fault_tap.hpp), feeds it time and requests, performs the control-unit Actions
// it returns, puts the endpoints in the power states it names (Power) and hands its events on;
// the tap and the endpoints' hook read the wire faults from scheduler(). Deterministic: no
// clock, no global random state.
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
  std::string name;  // FAULT_INJECTED, FAULT_CLEARED, POWER_OFF, POWER_ON, BOOTED, STATE_CHANGED
  nlohmann::json data;
  SimTime at{};
};

// D11 power_cycle (docs/decisions-local.md L-faults-5): on; off (dark: nothing in or out, no
// connection completed); booting (power back, connections from before reset, still dark for
// the scene's boot time); then on again.
enum class Power : std::uint8_t { on, off, booting };
std::string_view describe(Power power);  // "ON", "OFF", "BOOTING"

struct InjectorOutput {
  control::Actions actions;  // perform like any control-unit output
  // The power states entered, in order: the endpoints follow each (several in one call when
  // time jumped over a boot, or the boot time is 0).
  std::vector<Power> power_steps;
  std::vector<InjectorEvent> events;
};

class FaultInjector {
 public:
  // `head_dynamics`: the scene has D9's head_dynamics, so a stall coasts down (D11). `boot_time`:
  // after a power cycle's off time, how long the device boots before it serves (scanner.boot_s).
  FaultInjector(std::vector<faults::FaultSpec> scene_faults, std::uint64_t seed, bool head_dynamics,
                control::ControlUnit& unit, SimTime boot_time = SimTime::zero());

  // Simulated time reached `now`: triggers, expiries, power-on.
  InjectorOutput advance(SimTime now);
  // A request of `service` arrived on `transport` (before the control unit sees it); `seen`: all
  // of it, or the first frame or the rest of a multi-frame ISO-TP request (fault_scheduler.hpp).
  InjectorOutput on_request(SimTime now, std::uint16_t service, protocol::Transport transport,
                            faults::RequestSeen seen = faults::RequestSeen::whole);
  // The control socket's inject-fault; `id` is 0 when the entry waits for its trigger.
  InjectorOutput inject(SimTime now, faults::FaultSpec spec, faults::FaultId& id);
  // clear-fault: one (false when no such fault) or all.
  InjectorOutput clear(SimTime now, std::optional<faults::FaultId> id, bool& found);
  // After every control-unit event: a STATE_CHANGED event when the mode changed.
  void note_state(SimTime now, std::vector<InjectorEvent>& events);

  // While off or booting (power_cycle), nothing reaches the device and nothing leaves it.
  Power power() const { return power_on_at_ ? Power::off : booted_at_ ? Power::booting : Power::on; }
  std::optional<SimTime> next_deadline() const;
  nlohmann::json query_faults() const;
  faults::FaultScheduler& scheduler() { return scheduler_; }
  const faults::FaultScheduler& scheduler() const { return scheduler_; }
  // Events the wire faults produced (count used): turned into event lines by the caller.
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
  SimTime boot_time_;
  std::optional<SimTime> power_on_at_;  // off until then
  std::optional<SimTime> booted_at_;    // booting until then
  control::DeviceMode last_mode_;
  std::uint64_t injections_ = 0;
};

// JSON of one active fault for query-faults and events.
nlohmann::json fault_json(const faults::ActiveFault& fault);

}  // namespace ldoem::fault_injection
