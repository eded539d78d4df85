// D11 device faults: motor faults and ERROR, spontaneous resets, power-on, beam faults.
#include "ldoem/control/control_unit.hpp"

#include <algorithm>

#include "ldoem/control/revolution_timing.hpp"

namespace ldoem::control {

using protocol::MotorMode;
using protocol::Service;

namespace {

// D11: below 90 % of nominal speed the motor nibble says "spin too low".
constexpr double kSpinTooLowFraction = 0.9;
// D6: ECHO = 1000 * I_rs / I_rs_min, so 1000 is the detection threshold.
constexpr double kEchoAtThreshold = 1000.0;

SimTime one_revolution(double speed_hz) {
  return std::chrono::duration_cast<SimTime>(std::chrono::duration<double>(1.0 / speed_hz));
}

// SplitMix64's finaliser; a blind fraction picks beams per (seed, revolution, beam).
std::uint64_t mix64(std::uint64_t value) {
  value += 0x9E3779B97F4A7C15ULL;
  value = (value ^ (value >> 30)) * 0xBF58476D1CE4E5B9ULL;
  value = (value ^ (value >> 27)) * 0x94D049BB133111EBULL;
  return value ^ (value >> 31);
}

constexpr std::uint64_t kBlindStreamTag = 0xB11D'0000'0011ULL;

double blind_draw(std::uint64_t seed, std::uint64_t revolution, std::uint32_t beam) {
  const std::uint64_t bits = mix64(mix64(mix64(seed ^ kBlindStreamTag) + revolution) + beam);
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

}  // namespace

MotorMode settled_nibble(MotorFault fault) {
  switch (fault) {
    case MotorFault::stall: return MotorMode::fault;            // stopped: 0xB
    case MotorFault::overspeed: return MotorMode::spin_too_high;  // 0x9
    case MotorFault::encoder: return MotorMode::fault;          // 0xB
  }
  return MotorMode::fault;
}

bool in_sector(std::uint16_t angle_ticks, std::uint16_t from_ticks, std::uint16_t to_ticks) {
  if (from_ticks <= to_ticks) return angle_ticks >= from_ticks && angle_ticks < to_ticks;
  return angle_ticks >= from_ticks || angle_ticks < to_ticks;  // wraps through 0 deg
}

bool ControlUnit::allowed_in_error(std::uint16_t request_code) const {
  // D11: in ERROR every GET_* service, DO_RESET and CANCEL_PROFILE are answered; the rest gets
  // SERVICE_FAILURE reason 3. GET_PROFILE is answered too: by D2's reason 3 (not in MEASURE).
  switch (static_cast<Service>(request_code)) {
    case Service::get_identification:
    case Service::get_status:
    case Service::get_signal:
    case Service::get_config:
    case Service::get_sync_clock:
    case Service::get_function:
    case Service::get_profile:
    case Service::cancel_profile:
    case Service::do_reset:
      return true;
    default:
      return false;
  }
}

Actions ControlUnit::inject_motor_fault(SimTime now, MotorFault fault, bool decelerates) {
  Actions out;
  const std::vector<TimerId> live_before = live_timers();
  start_motor_fault(now, fault, decelerates, out);
  report_changes(out, live_before, std::nullopt);
  return out;
}

void ControlUnit::start_motor_fault(SimTime now, MotorFault fault, bool decelerates, Actions& out) {
  hardware_motor_fault_ = fault;
  if (state_.mode == DeviceMode::error || state_.motor_fault) return;  // already failing
  const double speed_hz = state_.head.speed_hz > 0 ? state_.head.speed_hz
                          : state_.spin_up         ? std::max(state_.spin_up->from_hz, state_.spin_up->to_hz)
                                                   : 0.0;
  if (speed_hz <= 0.0) return;  // latent: shows when the device next tries to spin
  stop_all_streams();               // D10: no profile after the fault

  MotorFaultCourse course;
  course.fault = fault;
  switch (fault) {
    case MotorFault::stall: {
      end_head_epoch(now);  // the head no longer turns at its nominal speed
      const SimTime to_low = decelerates ? head_.time_to_reach(speed_hz, kSpinTooLowFraction * speed_hz) : SimTime{0};
      const SimTime to_stop = decelerates ? head_.time_to_reach(speed_hz, 0.0) : SimTime{0};
      if (to_low < to_stop) course.steps.push_back({now + to_low, MotorMode::spin_too_low, false});
      course.steps.push_back({now + to_stop, MotorMode::fault, false});
      course.steps.push_back({now + std::min(to_low, to_stop) + one_revolution(speed_hz), std::nullopt, true});
      break;
    }
    case MotorFault::overspeed:
      course.steps.push_back({now, MotorMode::spin_too_high, false});
      course.steps.push_back({now + one_revolution(speed_hz), std::nullopt, true});
      break;
    case MotorFault::encoder:
      course.steps.push_back({now, MotorMode::fault, true});
      break;
  }
  std::stable_sort(course.steps.begin(), course.steps.end(),
                   [](const MotorFaultStep& a, const MotorFaultStep& b) { return a.at < b.at; });
  state_.motor_fault = std::move(course);
  run_motor_fault_steps(now, out);
}

void ControlUnit::run_motor_fault_steps(SimTime now, Actions& out) {
  if (!state_.motor_fault) return;
  MotorFaultCourse& course = *state_.motor_fault;
  course.timer.reset();
  while (!course.steps.empty() && course.steps.front().at <= now) {
    const MotorFaultStep step = course.steps.front();
    course.steps.erase(course.steps.begin());
    if (step.nibble) course.nibble = *step.nibble;
    if (step.enter_error) enter_error(step.at, out);
    if (!state_.motor_fault) return;
  }
  if (!course.steps.empty()) course.timer = arm_timer(out, course.steps.front().at);
}

void ControlUnit::enter_error(SimTime now, Actions& out) {
  stop_all_streams();
  const std::optional<ConnectionId> held_reply = state_.spin_up ? state_.spin_up->reply_to : std::nullopt;
  end_head_epoch(now);
  state_.spin_up.reset();
  state_.mode = DeviceMode::error;
  // A TRANS_ROTATE still waiting for the head gets its answer now: the status says ERROR.
  if (held_reply) reply(Event{now, *held_reply, out}, protocol::TransRotateReply{status_block()});
}

Actions ControlUnit::spontaneous_reset(SimTime now) {
  Actions out;
  const std::vector<TimerId> live_before = live_timers();
  stop_all_streams();
  state_.spin_up.reset();
  state_ = power_up_state(now, state_.flash);
  ++diagnostics_.spontaneous_resets;
  report_changes(out, live_before, std::nullopt);
  return out;
}

Actions ControlUnit::power_on(SimTime now) {
  Actions out;
  const std::vector<TimerId> live_before = live_timers();
  state_ = power_up_state(now, state_.flash);
  ++diagnostics_.power_cycles;
  report_changes(out, live_before, std::nullopt);
  return out;
}

void ControlUnit::apply_beam_faults(std::uint64_t revolution, std::span<const BeamQuery> beams,
                                    std::span<BeamReturn> returns) const {
  const double keep_power = 1.0 - beam_faults_.window_dirt;
  for (std::size_t i = 0; i < returns.size(); ++i) {
    BeamReturn& beam = returns[i];
    for (const BlindFault& blind : beam_faults_.blind) {
      const bool hit = blind.from_ticks ? in_sector(beams[i].angle_ticks, *blind.from_ticks, *blind.to_ticks)
                                        : blind_draw(beam_faults_.seed, revolution, beams[i].beam_index) < blind.fraction;
      if (hit) beam = BeamReturn{0, 0};
    }
    if (beam_faults_.window_dirt > 0.0 && beam.distance_q8_m != 0) {
      const double echo = beam.echo * keep_power;
      beam = echo < kEchoAtThreshold ? BeamReturn{0, 0}
                                     : BeamReturn{beam.distance_q8_m, static_cast<std::uint16_t>(echo + 0.5)};
    }
  }
}

}  // namespace ldoem::control
