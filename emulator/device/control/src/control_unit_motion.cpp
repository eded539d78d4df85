// State transitions (spec 5 with D2's entries), DO_RESET (spec 3.3, D3) and the head's speed
// changes (lead decision 4, D7).
#include "ldoem/control/control_unit.hpp"

#include "ldoem/control/revolution_timing.hpp"
#include "ldoem/control/sector_table.hpp"

namespace ldoem::control {

using protocol::FailureReason;
using protocol::Service;

void ControlUnit::end_head_epoch(SimTime now) {
  if (state_.head.speed_hz == 0) return;
  state_.head.revolutions_before_epoch +=
      first_revolution_starting_at_or_after(state_.head.epoch_start, state_.head.speed_hz, now);
  state_.head.speed_hz = 0;
  state_.head.epoch_start = now;
}

void ControlUnit::stop_head(SimTime now) {
  end_head_epoch(now);
  state_.spin_up.reset();  // a held TRANS_ROTATE reply is never sent
}

void ControlUnit::begin_spin(const Event& event, std::uint16_t to_hz) {
  const std::uint16_t from_hz = state_.head.speed_hz;
  end_head_epoch(event.now);  // no revolutions are counted while the speed changes
  const SimTime reached_at = event.now + head_.time_to_reach(from_hz, to_hz);
  const TimerId timer = arm_timer(event.out, reached_at);
  state_.spin_up = SpinUp{from_hz, to_hz, reached_at, timer, event.from};
  state_.mode = DeviceMode::rotate;
}

void ControlUnit::complete_spin(SimTime /*now*/, Actions& out) {
  const SpinUp spin = *state_.spin_up;
  state_.spin_up.reset();
  // The epoch starts at the computed time, not at the (possibly late) timer delivery, so the
  // revolution grid does not depend on the daemon's latency.
  state_.head.speed_hz = spin.to_hz;
  state_.head.epoch_start = spin.reached_at;
  state_.mode = DeviceMode::rotate;
  if (spin.reply_to) {
    const Event event{spin.reached_at, *spin.reply_to, out};
    reply(event, protocol::TransRotateReply{status_block()});
  }
}

void ControlUnit::serve(const Event& event, const protocol::TransIdle&) {
  if (state_.spin_up) {  // lead decision 4: no transition while the head changes speed
    fail(event, Service::trans_idle, FailureReason::wrong_state);
    return;
  }
  switch (state_.mode) {
    case DeviceMode::measure:  // D2: MEASURE -> IDLE must pass through ROTATE
      fail(event, Service::trans_idle, FailureReason::wrong_state);
      return;
    case DeviceMode::idle:  // D2: a transition to the current state answers the status
      break;
    case DeviceMode::error:  // D11: refused in handle_request (reason 3); DO_RESET 2 leaves ERROR
      fail(event, Service::trans_idle, FailureReason::wrong_state);
      return;
    case DeviceMode::rotate:
      stop_head(event.now);
      state_.mode = DeviceMode::idle;
      break;
  }
  reply(event, protocol::TransIdleReply{status_block()});
}

void ControlUnit::serve(const Event& event, const protocol::TransRotate& request) {
  if (state_.spin_up || state_.mode == DeviceMode::error) {
    fail(event, Service::trans_rotate, FailureReason::wrong_state);
    return;
  }
  // Spec 3.3: 0 = the configured (flash) speed, 1..4 reserved, 5..20 Hz.
  constexpr std::uint16_t kUseFlashSpeed = 0;
  if (request.frequency_hz != kUseFlashSpeed &&
      (request.frequency_hz < kMinMotorSpeedHz || request.frequency_hz > kMaxMotorSpeedHz)) {
    fail(event, Service::trans_rotate, FailureReason::out_of_range);
    return;
  }
  const std::uint16_t target_hz =
      request.frequency_hz == kUseFlashSpeed ? state_.flash.global.motor_speed_hz : request.frequency_hz;
  if (hardware_motor_fault_) {
    // D11: a motor that has not been repaired fails as soon as the device tries to spin it.
    stop_all_streams();
    MotorFaultCourse course;
    course.fault = *hardware_motor_fault_;
    course.steps.push_back({event.now, settled_nibble(*hardware_motor_fault_), true});
    state_.motor_fault = std::move(course);
    run_motor_fault_steps(event.now, event.out);
    reply(event, protocol::TransRotateReply{status_block()});
    return;
  }
  if (state_.mode == DeviceMode::measure) {
    stop_all_streams();  // D10: before the reply, so no profile follows it
    state_.mode = DeviceMode::rotate;
  }
  if (state_.mode == DeviceMode::rotate && state_.head.speed_hz == target_hz) {
    reply(event, protocol::TransRotateReply{status_block()});
    return;
  }
  begin_spin(event, target_hz);  // the reply waits for on_timer (D7)
}

void ControlUnit::serve(const Event& event, const protocol::TransMeasure&) {
  // A head that stalls or races (D11: the revolution before ERROR) cannot measure: refused like
  // every request ERROR refuses, which follows within that revolution (L-faults-6).
  if (state_.spin_up || state_.motor_fault) {
    fail(event, Service::trans_measure, FailureReason::wrong_state);
    return;
  }
  switch (state_.mode) {
    case DeviceMode::idle:   // D2: IDLE -> MEASURE must pass through ROTATE
    case DeviceMode::error:
      fail(event, Service::trans_measure, FailureReason::wrong_state);
      return;
    case DeviceMode::measure:
      reply(event, protocol::TransMeasureReply{status_block(), protocol::measure_return::kOk});
      return;
    case DeviceMode::rotate:
      break;
  }
  const MeasureCheck check = check_measure_configuration(
      state_.ram.sectors, state_.ram.global.angle_step_ticks, state_.head.speed_hz);
  if (check == MeasureCheck::ok) state_.mode = DeviceMode::measure;
  // Spec 3.3: a refusal keeps ROTATE and reports the code in the RETURNCODE word.
  reply(event, protocol::TransMeasureReply{status_block(), static_cast<std::uint16_t>(check)});
}

void ControlUnit::serve(const Event& event, const protocol::DoReset& request) {
  namespace level = protocol::reset_level;
  switch (request.level) {
    case level::kFull:
    case level::kRestart:
      // D3: answer first, then reset; streams stop before the reply (D10). The reset itself is
      // instantaneous: IDLE, motor stopped, RAM = flash, clock 0 (D4).
      stop_all_streams();
      state_.spin_up.reset();
      reply(event, protocol::DoResetReply{request.level});
      state_ = power_up_state(event.now, state_.flash);
      return;
    case level::kHaltToIdle:
      stop_all_streams();
      stop_head(event.now);
      state_.mode = DeviceMode::idle;  // D11: also out of ERROR
      state_.motor_fault.reset();
      reply(event, protocol::DoResetReply{request.level});
      return;
    case level::kReloadApdVoltage:  // D3: accepted, changes nothing
      reply(event, protocol::DoResetReply{request.level});
      return;
    default:  // the decoder refuses other levels; kept for safety
      fail(event, Service::do_reset, FailureReason::out_of_range);
      return;
  }
}

}  // namespace ldoem::control
