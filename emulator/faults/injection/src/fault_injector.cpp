#include "ldoem/fault_injection/fault_injector.hpp"

#include <algorithm>

namespace ldoem::fault_injection {
namespace {

using faults::FaultEventKind;
using faults::FaultKind;

double seconds(SimTime t) { return std::chrono::duration<double>(t).count(); }

std::optional<control::MotorFault> motor_fault_of(FaultKind kind) {
  switch (kind) {
    case FaultKind::motor_stall: return control::MotorFault::stall;
    case FaultKind::motor_overspeed: return control::MotorFault::overspeed;
    case FaultKind::encoder_error: return control::MotorFault::encoder;
    default: return std::nullopt;
  }
}

void append(control::Actions& into, control::Actions from) {
  for (auto& telegram : from.telegrams) into.telegrams.push_back(std::move(telegram));
  for (const auto& cancelled : from.cancelled_timers) into.cancelled_timers.push_back(cancelled);
  std::erase_if(into.timers, [&from](const control::TimerRequest& timer) {
    return std::find(from.cancelled_timers.begin(), from.cancelled_timers.end(), timer.id) != from.cancelled_timers.end();
  });
  for (const auto& timer : from.timers) into.timers.push_back(timer);
  if (from.flash_image) into.flash_image = std::move(from.flash_image);
  if (from.head_target_hz) into.head_target_hz = from.head_target_hz;
  if (from.can_config) into.can_config = std::move(from.can_config);
}

}  // namespace

std::string_view describe(Power power) {
  switch (power) {
    case Power::on: return "ON";
    case Power::off: return "OFF";
    case Power::booting: return "BOOTING";
  }
  return "ON";
}

nlohmann::json fault_json(const faults::ActiveFault& fault) {
  nlohmann::json item{{"id", fault.id},
                      {"kind", std::string(faults::fault_name(fault.spec.kind))},
                      {"origin", fault.origin},
                      {"since_s", seconds(fault.since)},
                      {"description", faults::describe(fault.spec)}};
  if (fault.until) item["until_s"] = seconds(*fault.until);
  if (fault.remaining) item["remaining"] = *fault.remaining;
  return item;
}

FaultInjector::FaultInjector(std::vector<faults::FaultSpec> scene_faults, std::uint64_t seed, bool head_dynamics,
                             control::ControlUnit& unit, SimTime boot_time)
    : scheduler_(std::move(scene_faults), seed),
      seed_(seed),
      head_dynamics_(head_dynamics),
      unit_(unit),
      boot_time_(boot_time),
      last_mode_(unit.state().mode) {}

void FaultInjector::events_from(const std::vector<faults::FaultEvent>& fault_events, InjectorOutput& out) {
  for (const faults::FaultEvent& event : fault_events) {
    nlohmann::json data{{"id", event.id}, {"kind", std::string(faults::fault_name(event.kind))}, {"reason", event.reason}};
    if (event.what == FaultEventKind::injected) {
      ++injections_;
      for (const auto& active : scheduler_.active()) {
        if (active.id == event.id) data["description"] = faults::describe(active.spec);
      }
    }
    out.events.push_back({event.what == FaultEventKind::injected ? "FAULT_INJECTED" : "FAULT_CLEARED", data, event.at});
  }
}

void FaultInjector::react(const std::vector<faults::FaultEvent>& fault_events, InjectorOutput& out) {
  events_from(fault_events, out);
  bool beams_changed = false;
  bool motor_changed = false;
  for (const faults::FaultEvent& event : fault_events) {
    const SimTime now = event.at;
    if (motor_fault_of(event.kind)) motor_changed = true;
    if (event.kind == FaultKind::blind || event.kind == FaultKind::window_dirt) beams_changed = true;
    if (event.what != FaultEventKind::injected) continue;
    if (const auto motor = motor_fault_of(event.kind)) {
      if (power() != Power::off) append(out.actions, unit_.inject_motor_fault(now, *motor, head_dynamics_));
    } else if (event.kind == FaultKind::reset_spontaneous) {
      if (power() == Power::on) append(out.actions, unit_.spontaneous_reset(now));
      std::vector<faults::FaultEvent> acted;
      scheduler_.acted(now, event.id, acted);
      events_from(acted, out);
    } else if (event.kind == FaultKind::power_cycle) {
      const faults::ActiveFault* fault = nullptr;
      for (const auto& active : scheduler_.active()) {
        if (active.id == event.id) fault = &active;
      }
      const SimTime off = fault ? fault->spec.off : SimTime{std::chrono::seconds(1)};
      if (power() != Power::off) {
        out.power_steps.push_back(Power::off);
        out.events.push_back({"POWER_OFF", {{"off_s", seconds(off)}}, now});
      }
      booted_at_.reset();  // a cut while booting: the boot starts again after this off time
      power_on_at_ = now + off;  // a second cycle while off: dark until off_s after it
      std::vector<faults::FaultEvent> acted;
      scheduler_.acted(now, event.id, acted);
      events_from(acted, out);
    }
  }
  if (motor_changed) update_motor_fault();
  if (beams_changed) update_beam_faults();
}

void FaultInjector::update_motor_fault() {
  bool any = false;
  for (const auto& active : scheduler_.active()) any = any || motor_fault_of(active.spec.kind).has_value();
  if (!any) unit_.clear_motor_fault();  // D11: cleared; DO_RESET 2 then returns to IDLE
}

void FaultInjector::update_beam_faults() {
  control::BeamFaults beams;
  beams.seed = seed_;
  for (const auto& active : scheduler_.active()) {
    if (active.spec.kind == FaultKind::blind) {
      beams.blind.push_back(control::BlindFault{active.spec.from_ticks, active.spec.to_ticks, active.spec.fraction.value_or(0.0)});
    } else if (active.spec.kind == FaultKind::window_dirt) {
      beams.window_dirt = std::max(beams.window_dirt, active.spec.fraction.value_or(0.0));
    }
  }
  unit_.set_beam_faults(std::move(beams));
}

InjectorOutput FaultInjector::advance(SimTime now) {
  InjectorOutput out;
  if (power_on_at_ && *power_on_at_ <= now) {
    // Power back: the device's clock starts (D4 power-up state), its old connections are reset,
    // and it serves once booted (L-faults-5).
    const SimTime on_at = *power_on_at_;
    power_on_at_.reset();
    booted_at_ = on_at + boot_time_;
    append(out.actions, unit_.power_on(on_at));
    out.power_steps.push_back(Power::booting);
    out.events.push_back({"POWER_ON", {{"boot_s", seconds(boot_time_)}}, on_at});
  }
  if (booted_at_ && *booted_at_ <= now) {
    const SimTime ready_at = *booted_at_;
    booted_at_.reset();
    out.power_steps.push_back(Power::on);
    out.events.push_back({"BOOTED", nlohmann::json::object(), ready_at});
  }
  std::vector<faults::FaultEvent> fault_events;
  scheduler_.advance(now, fault_events);
  react(fault_events, out);
  note_state(now, out.events);
  return out;
}

InjectorOutput FaultInjector::on_request(SimTime now, std::uint16_t service, protocol::Transport transport,
                                         faults::RequestSeen seen) {
  InjectorOutput out;
  std::vector<faults::FaultEvent> fault_events;
  scheduler_.on_request(now, service, transport, fault_events, seen);
  react(fault_events, out);
  note_state(now, out.events);
  return out;
}

InjectorOutput FaultInjector::inject(SimTime now, faults::FaultSpec spec, faults::FaultId& id) {
  InjectorOutput out;
  std::vector<faults::FaultEvent> fault_events;
  id = scheduler_.inject(now, std::move(spec), fault_events);
  react(fault_events, out);
  note_state(now, out.events);
  return out;
}

InjectorOutput FaultInjector::clear(SimTime now, std::optional<faults::FaultId> id, bool& found) {
  InjectorOutput out;
  std::vector<faults::FaultEvent> fault_events;
  found = true;
  if (id) {
    found = scheduler_.clear(now, *id, fault_events);
  } else {
    scheduler_.clear_all(now, "cleared", fault_events);
  }
  react(fault_events, out);
  return out;
}

void FaultInjector::note_state(SimTime now, std::vector<InjectorEvent>& events) {
  const control::DeviceMode mode = unit_.state().mode;
  if (mode == last_mode_) return;
  events.push_back({"STATE_CHANGED",
                    {{"from", std::string(control::describe(last_mode_))}, {"to", std::string(control::describe(mode))},
                     {"status_byte", unit_.status_byte().to_byte()}},
                    now});
  last_mode_ = mode;
}

std::optional<SimTime> FaultInjector::next_deadline() const {
  std::optional<SimTime> deadline = scheduler_.next_deadline();
  for (const auto& power_change : {power_on_at_, booted_at_}) {
    if (power_change && (!deadline || *power_change < *deadline)) deadline = power_change;
  }
  return deadline;
}

nlohmann::json FaultInjector::query_faults() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& active : scheduler_.active()) list.push_back(fault_json(active));
  return list;
}

}  // namespace ldoem::fault_injection
