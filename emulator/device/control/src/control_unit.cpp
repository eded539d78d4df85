// Construction, dispatch of requests and timers, and the helpers every service uses.
#include "ldoem/control/control_unit.hpp"

#include <algorithm>
#include <sstream>

#include "ldoem/control/flash_image.hpp"
#include "ldoem/protocol/bytes.hpp"

namespace ldoem::control {

using protocol::FailureReason;
using protocol::Service;

std::string_view describe(DeviceMode mode) {
  switch (mode) {
    case DeviceMode::idle: return "IDLE";
    case DeviceMode::rotate: return "ROTATE";
    case DeviceMode::measure: return "MEASURE";
    case DeviceMode::error: return "ERROR";
  }
  return "unknown";
}

DeviceState power_up_state(SimTime now, const DeviceConfig& flash) {
  DeviceState state;
  state.mode = DeviceMode::idle;
  state.head = HeadState{};
  state.spin_up.reset();
  state.streams.clear();
  state.revolution_timer.reset();
  state.ram = flash;
  state.flash = flash;
  state.clock = DeviceClock::reading(now, 0);
  state.port_value = 0;
  state.motor_fault.reset();
  return state;
}

ControlUnit::ControlUnit(Setup setup, const HeadModel& head, MeasurementSource& measurement)
    : setup_(std::move(setup)),
      head_(head),
      measurement_(measurement),
      state_(power_up_state(setup_.power_up_time, setup_.flash)),
      reported_can_config_(state_.ram.can) {}

std::vector<TimerId> ControlUnit::live_timers() const {
  std::vector<TimerId> live;
  if (state_.spin_up) live.push_back(state_.spin_up->timer);
  if (state_.revolution_timer) live.push_back(state_.revolution_timer->timer);
  if (state_.motor_fault && state_.motor_fault->timer) live.push_back(*state_.motor_fault->timer);  // D11
  return live;
}

void ControlUnit::report_changes(Actions& out, const std::vector<TimerId>& live_before, std::optional<TimerId> fired) {
  const std::vector<TimerId> live_after = live_timers();
  const auto still_live = [&live_after](TimerId id) {
    return std::find(live_after.begin(), live_after.end(), id) != live_after.end();
  };
  for (const TimerId id : live_before) {
    if (id != fired && !still_live(id)) out.cancelled_timers.push_back(id);
  }
  // A timer armed and made stale within this one event is simply not asked for.
  std::erase_if(out.timers, [&still_live](const TimerRequest& timer) { return !still_live(timer.id); });

  const std::pair<std::uint16_t, SimTime> head_target =
      state_.spin_up ? std::pair{state_.spin_up->to_hz, state_.spin_up->reached_at}
                     : std::pair{state_.head.speed_hz, state_.head.epoch_start};
  // A spin-up that completes keeps its key (to_hz, reached_at): completion is not a new target.
  if (head_target != reported_head_target_) {
    reported_head_target_ = head_target;
    out.head_target_hz = head_target.first;
  }
  if (state_.ram.can != reported_can_config_) {
    reported_can_config_ = state_.ram.can;
    out.can_config = state_.ram.can;
  }
}

Actions ControlUnit::handle_request(SimTime now, ConnectionId from, protocol::ByteView payload,
                                    const TransportQuery& /*transport: profiles only, see on_timer*/) {
  Actions out;
  const Event event{now, from, out};
  auto request = protocol::decode_request(payload);
  if (!request) {
    const protocol::RequestError& error = request.error();
    // D2: SET_CONFIG has an in-band error for an unacceptable value (a key without a layout).
    if (error.request_code == protocol::code_of(Service::set_config) &&
        error.reason == FailureReason::out_of_range) {
      reply(event, protocol::SetConfigReply{protocol::kSetConfigRefused});
      return out;
    }
    ++diagnostics_.service_failures_sent;
    reply(event, protocol::ServiceFailure{error.request_code, error.reason});
    return out;
  }
  // D11: in ERROR only GET_*, DO_RESET and CANCEL_PROFILE are served (the payload decoded, so
  // it holds a request code).
  const std::uint16_t request_code = protocol::read_word_be(payload, 0);
  if (state_.mode == DeviceMode::error && !allowed_in_error(request_code)) {
    ++diagnostics_.service_failures_sent;
    reply(event, protocol::ServiceFailure{request_code, FailureReason::wrong_state});
    return out;
  }
  const std::vector<TimerId> live_before = live_timers();
  std::visit([this, &event](const auto& typed) { serve(event, typed); }, *request);
  report_changes(out, live_before, std::nullopt);
  return out;
}

Actions ControlUnit::on_timer(SimTime now, TimerId timer, const TransportQuery& transport) {
  Actions out;
  const std::vector<TimerId> live_before = live_timers();
  if (state_.spin_up && state_.spin_up->timer == timer) {
    complete_spin(now, out);
  } else if (state_.revolution_timer && state_.revolution_timer->timer == timer) {
    const std::uint64_t revolution = state_.revolution_timer->revolution;
    state_.revolution_timer.reset();
    emit_profiles(now, revolution, transport, out);
  } else if (state_.motor_fault && state_.motor_fault->timer == timer) {
    run_motor_fault_steps(now, out);
  }
  // Any other id belongs to something a reset or a stop made obsolete: nothing to do.
  report_changes(out, live_before, timer);
  return out;
}

Actions ControlUnit::on_framing_error(SimTime now, ConnectionId from, const protocol::FramingError& error) {
  Actions out;
  const Event event{now, from, out};
  ++diagnostics_.service_failures_sent;
  reply(event, protocol::ServiceFailure{error.request_code, protocol::failure_reason_for_framing(error.detail)});
  return out;
}

Actions ControlUnit::on_connection_closed(SimTime /*now: nothing here depends on it*/, ConnectionId connection) {
  Actions out;
  const std::vector<TimerId> live_before = live_timers();
  state_.streams.erase(connection);
  if (state_.streams.empty()) state_.revolution_timer.reset();
  if (state_.spin_up && state_.spin_up->reply_to == connection) state_.spin_up->reply_to.reset();
  report_changes(out, live_before, std::nullopt);
  return out;
}

protocol::StatusByte ControlUnit::status_byte() const {
  protocol::StatusByte status;
  switch (state_.mode) {
    case DeviceMode::idle: status.sensor = protocol::SensorMode::idle; break;
    case DeviceMode::rotate: status.sensor = protocol::SensorMode::rotate; break;
    case DeviceMode::measure: status.sensor = protocol::SensorMode::measure; break;
    case DeviceMode::error: status.sensor = protocol::SensorMode::error; break;
  }
  // Lead decision 4: while the head is still changing speed the motor nibble says so (spec 2.4).
  status.motor = protocol::MotorMode::ok;
  if (state_.spin_up) {
    status.motor = state_.spin_up->to_hz > state_.spin_up->from_hz ? protocol::MotorMode::spin_too_low
                                                                   : protocol::MotorMode::spin_too_high;
  }
  if (state_.motor_fault && state_.motor_fault->nibble != protocol::MotorMode::ok) {
    status.motor = state_.motor_fault->nibble;  // D11
  }
  return status;
}

protocol::StatusBlock ControlUnit::status_block() const {
  return protocol::StatusBlock{{}, status_byte()};  // D3: bytes 0..2 are 0x00
}

void ControlUnit::reply(const Event& event, const protocol::Response& response) {
  event.out.telegrams.push_back(
      OutgoingTelegram{event.from, protocol::encode_response(response), TelegramKind::reply});
}

void ControlUnit::fail(const Event& event, Service service, FailureReason reason) {
  ++diagnostics_.service_failures_sent;
  reply(event, protocol::ServiceFailure{protocol::code_of(service), reason});
}

TimerId ControlUnit::arm_timer(Actions& out, SimTime at) {
  const TimerId id{next_timer_id_++};
  out.timers.push_back(TimerRequest{at, id});
  return id;
}

bool ControlUnit::write_flash(Actions& out, const DeviceConfig& flash) {
  if (flash == state_.flash) return true;
  protocol::Bytes image = serialise_flash_image(flash);
  if (setup_.flash_store != nullptr && !setup_.flash_store->save(image)) return false;  // logged by the store's owner
  state_.flash = flash;
  out.flash_image = std::move(image);
  return true;
}

namespace {

void dump_config(std::ostringstream& text, std::string_view name, const DeviceConfig& config) {
  const auto& g = config.global;
  text << name << ".global: id " << g.sensor_id << ", " << g.motor_speed_hz << " Hz, step "
       << g.angle_step_ticks << " ticks\n";
  text << name << ".interlace: " << config.interlace.mode << "\n";
  const auto& e = config.ethernet;
  text << name << ".ethernet: ip " << e.ip_address[0] << "." << e.ip_address[1] << "." << e.ip_address[2]
       << "." << e.ip_address[3] << " mask " << e.subnet_mask[0] << "." << e.subnet_mask[1] << "."
       << e.subnet_mask[2] << "." << e.subnet_mask[3] << " gw " << e.gateway[0] << "." << e.gateway[1]
       << "." << e.gateway[2] << "." << e.gateway[3] << " node " << e.node_id << " port "
       << e.transparent_tcp_port << "\n";
  const auto& s = config.serial;
  text << name << ".serial: baud code " << s.baud_code << ", parity " << s.parity << ", stop "
       << s.stop_bits << ", data " << s.data_bits << "\n";
  const auto& c = config.can;
  text << name << ".can: bitrate code " << c.bitrate_code << ", request 0x" << std::hex << c.request_id
       << ", response 0x" << c.response_id << std::dec << ", bs " << c.block_size << ", stmin "
       << c.st_min_ms << "\n";
  text << name << ".near_field_filter: " << (config.near_field_filter_on ? "on" : "off") << "\n";
  for (std::size_t i = 0; i < config.sectors.size(); ++i) {
    text << name << ".sector[" << i << "]: function " << config.sectors[i].function << ", stop "
         << config.sectors[i].stop_ticks << "\n";
  }
}

}  // namespace

std::string ControlUnit::dump(SimTime now) const {
  std::ostringstream text;
  text << "mode: " << describe(state_.mode) << "\n";
  text << "status byte: 0x" << std::hex << unsigned{status_byte().to_byte()} << std::dec << "\n";
  text << "head: " << state_.head.speed_hz << " Hz, epoch " << state_.head.epoch_start.count()
       << " ns, revolutions before epoch " << state_.head.revolutions_before_epoch << "\n";
  if (state_.spin_up) {
    const SpinUp& spin = *state_.spin_up;
    text << "spin_up: " << spin.from_hz << " -> " << spin.to_hz << " Hz at " << spin.reached_at.count()
         << " ns, timer " << spin.timer.value << ", reply to "
         << (spin.reply_to ? to_string(*spin.reply_to) : std::string("nobody")) << "\n";
  } else {
    text << "spin_up: none\n";
  }
  text << "streams: " << state_.streams.size() << "\n";
  for (const auto& [connection, stream] : state_.streams) {
    text << "  " << to_string(connection) << ": format 0x" << std::hex << stream.format << std::dec
         << ", wanted " << stream.profiles_wanted << ", sent " << stream.profiles_sent
         << ", first revolution " << stream.next_revolution << "\n";
  }
  if (state_.revolution_timer) {
    text << "revolution_timer: revolution " << state_.revolution_timer->revolution << ", timer "
         << state_.revolution_timer->timer.value << "\n";
  } else {
    text << "revolution_timer: none\n";
  }
  text << "clock: " << state_.clock.value_at(now) << " ms (offset " << state_.clock.offset_ms() << ")\n";
  text << "port_value: 0x" << std::hex << state_.port_value << std::dec << "\n";
  if (state_.motor_fault) {
    text << "motor_fault: " << static_cast<int>(state_.motor_fault->fault) << ", nibble 0x" << std::hex
         << static_cast<unsigned>(state_.motor_fault->nibble) << std::dec << ", steps left "
         << state_.motor_fault->steps.size() << "\n";
  } else {
    text << "motor_fault: none\n";
  }
  dump_config(text, "ram", state_.ram);
  dump_config(text, "flash", state_.flash);
  text << "diagnostics: skipped_profiles " << diagnostics_.skipped_profiles << ", profiles_sent "
       << diagnostics_.profiles_sent << ", service_failures_sent " << diagnostics_.service_failures_sent
       << ", spontaneous_resets " << diagnostics_.spontaneous_resets << ", power_cycles "
       << diagnostics_.power_cycles << "\n";
  return text.str();
}

}  // namespace ldoem::control
