// Status, configuration, clock and sector-table services (spec 3.3, 3.4, 3.6; D2 state rules).
#include "ldoem/control/control_unit.hpp"

namespace ldoem::control {

using protocol::FailureReason;
using protocol::Service;

void ControlUnit::serve(const Event& event, const protocol::GetIdentification& request) {
  const auto text = setup_.identification.find(request.item);
  if (text == setup_.identification.end()) {
    fail(event, Service::get_identification, FailureReason::out_of_range);
    return;
  }
  reply(event, protocol::IdentificationReply{text->second});  // D3: no NUL, no padding
}

void ControlUnit::serve(const Event& event, const protocol::GetStatus&) {
  reply(event, protocol::GetStatusReply{status_block(), {}});
}

void ControlUnit::serve(const Event& event, const protocol::GetSignal&) {
  reply(event, protocol::GetSignalReply{state_.port_value});
}

void ControlUnit::serve(const Event& event, const protocol::SetSignal& request) {
  // Spec 3.3: SET_SIGNAL replaces the whole port; D3: the reply is 81 05 00 00 in every state.
  state_.port_value = request.port_value;
  reply(event, protocol::SetSignalReply{0x0000});
}

void ControlUnit::serve(const Event& event, const protocol::SetConfig& request) {
  // D2: only in IDLE, otherwise (and for an unacceptable value) the in-band result 0x0001.
  if (state_.mode != DeviceMode::idle || state_.spin_up) {
    reply(event, protocol::SetConfigReply{protocol::kSetConfigRefused});
    return;
  }
  DeviceConfig ram = state_.ram;
  if (apply_config_body(ram, request.body)) {
    reply(event, protocol::SetConfigReply{protocol::kSetConfigRefused});
    return;
  }
  // Lead decision 2: SET_CONFIG writes RAM and flash for its key; the global key also commits
  // the RAM sector table (S1's observation, spec 3.3).
  DeviceConfig flash = state_.flash;
  [[maybe_unused]] const auto flash_issue = apply_config_body(flash, request.body);
  if (protocol::key_of(request.body) == protocol::ConfigKey::global) flash.sectors = ram.sectors;
  if (!write_flash(event.out, flash)) {  // L-flash-1: not stored, nothing changes
    reply(event, protocol::SetConfigReply{protocol::kSetConfigRefused});
    return;
  }
  state_.ram = ram;
  reply(event, protocol::SetConfigReply{protocol::kSetConfigSuccess});
}

void ControlUnit::serve(const Event& event, const protocol::GetConfig& request) {
  auto body = config_body_for(state_.ram, static_cast<protocol::ConfigKey>(request.key));
  if (!body) {
    fail(event, Service::get_config, FailureReason::out_of_range);
    return;
  }
  reply(event, protocol::GetConfigReply{*body});
}

void ControlUnit::serve(const Event& event, const protocol::SetTimeAbs& request) {
  if (state_.mode == DeviceMode::measure) {  // spec 3.3 (S1), D2
    fail(event, Service::set_time_abs, FailureReason::wrong_state);
    return;
  }
  state_.clock.set(event.now, request.time_ms);
  reply(event, protocol::SetTimeAbsReply{state_.clock.value_at(event.now)});
}

void ControlUnit::serve(const Event& event, const protocol::SetTimeRel& request) {
  if (state_.mode == DeviceMode::measure) {
    fail(event, Service::set_time_rel, FailureReason::wrong_state);
    return;
  }
  state_.clock.add(request.delta_ms);
  reply(event, protocol::SetTimeRelReply{state_.clock.value_at(event.now)});
}

void ControlUnit::serve(const Event& event, const protocol::GetSyncClock&) {
  reply(event, protocol::SyncClockReply{state_.clock.value_at(event.now)});
}

void ControlUnit::serve(const Event& event, const protocol::SetFilter& request) {
  // Item and value were checked by the decoder (item 1, value 0/1; else reason 4).
  if (state_.mode == DeviceMode::measure) {
    fail(event, Service::set_filter, FailureReason::wrong_state);
    return;
  }
  // Spec 3.3: the filter setting is stored in flash. D14 (near_field_filter.hpp) says what it does.
  DeviceConfig flash = state_.flash;
  flash.near_field_filter_on = request.value == 1;
  if (!write_flash(event.out, flash)) {  // L-flash-1: SET_FILTER has no in-band error
    fail(event, Service::set_filter, FailureReason::flash_not_stored);
    return;
  }
  state_.ram.near_field_filter_on = flash.near_field_filter_on;
  reply(event, protocol::SetFilterReply{request.item});
}

void ControlUnit::serve(const Event& event, const protocol::SetFunction& request) {
  // Spec 3.3: FF FF for an invalid request; D2: also in MEASURE.
  const Sector sector{request.function, request.stop_ticks};
  if (state_.mode == DeviceMode::measure || request.sector >= kSectorSlots || !sector_entry_acceptable(sector)) {
    reply(event, protocol::SetFunctionReply{protocol::kSetFunctionInvalid});
    return;
  }
  constexpr std::uint16_t kWriteToFlash = 1;  // spec 3.3: any other value is temporary
  if (request.flash_flag == kWriteToFlash) {
    DeviceConfig flash = state_.flash;
    flash.sectors[request.sector] = sector;
    if (!write_flash(event.out, flash)) {  // L-flash-1: not stored, nothing changes
      reply(event, protocol::SetFunctionReply{protocol::kSetFunctionInvalid});
      return;
    }
  }
  state_.ram.sectors[request.sector] = sector;
  reply(event, protocol::SetFunctionReply{request.sector});  // D3
}

void ControlUnit::serve(const Event& event, const protocol::GetFunction& request) {
  if (request.sector >= kSectorSlots) {  // the decoder refuses it already; never index past the table
    fail(event, Service::get_function, FailureReason::out_of_range);
    return;
  }
  const Sector& sector = state_.ram.sectors[request.sector];
  reply(event, protocol::GetFunctionReply{request.sector, sector.function, sector.stop_ticks});
}

}  // namespace ldoem::control
