// GET_PROFILE / CANCEL_PROFILE and the profile stream (spec 3.5, D3, D10, lead decision 5).
#include "ldoem/control/control_unit.hpp"

#include <algorithm>
#include <vector>

#include "ldoem/control/near_field_filter.hpp"
#include "ldoem/control/revolution_timing.hpp"
#include "ldoem/control/sector_table.hpp"

namespace ldoem::control {

using protocol::FailureReason;
using protocol::Service;

namespace {

// Spec 3.5: bits 14 and 15 of PROFILEFORMAT have no published meaning; lead decision 5 refuses them.
constexpr std::uint16_t kUnpublishedFormatBits = 0xC000;

bool transport_is_size_limited(protocol::Transport kind) {
  switch (kind) {
    case protocol::Transport::tcp:
    case protocol::Transport::serial: return true;   // D3: 5816 payload bytes
    case protocol::Transport::can: return false;     // D1/D3: ISO-TP has no such limit
    case protocol::Transport::lpt: break;            // no telegrams: never asked
  }
  return true;
}

}  // namespace

std::size_t ControlUnit::profile_payload_bytes(std::uint16_t format) const {
  std::vector<std::size_t> points;
  for (const SectorGeometry& sector : sector_geometry(state_.ram.sectors, state_.ram.global.angle_step_ticks)) {
    points.push_back(sector.point_count);
  }
  return protocol::profile_payload_size(format, points);
}

void ControlUnit::stop_all_streams() {
  state_.streams.clear();
  state_.revolution_timer.reset();  // its timer, when it fires, is stale and ignored
}

void ControlUnit::serve(const Event& event, const protocol::GetProfile& request) {
  if (state_.mode != DeviceMode::measure) {  // D2
    fail(event, Service::get_profile, FailureReason::wrong_state);
    return;
  }
  if ((request.format & kUnpublishedFormatBits) != 0) {
    fail(event, Service::get_profile, FailureReason::out_of_range);
    return;
  }
  if (transport_is_size_limited(event.from.kind) &&
      profile_payload_bytes(request.format) > protocol::kMaxTelegramPayload) {
    fail(event, Service::get_profile, FailureReason::out_of_range);  // D3
    return;
  }
  // A stalled head (D11 motor_stall: MEASURE at 0 Hz until ERROR) turns no revolution, so no
  // stream starts and no profile comes, as for a stream the stall stopped.
  if (state_.head.speed_hz == 0) {
    state_.streams.erase(event.from);
    return;
  }
  // The first profile is that of the first revolution starting at or after the request; a new
  // GET_PROFILE replaces the connection's stream and restarts PROFILESENT (D3). The answer is
  // the stream itself: no reply telegram (spec 3.5).
  ProfileStream stream;
  stream.format = request.format;
  stream.profiles_wanted = request.profile_count;
  stream.profiles_sent = 0;
  stream.next_revolution =
      first_revolution_starting_at_or_after(state_.head.epoch_start, state_.head.speed_hz, event.now);
  state_.streams[event.from] = stream;
  ensure_revolution_timer(event.out);
}

void ControlUnit::serve(const Event& event, const protocol::CancelProfile&) {
  // D11: in ERROR it is answered with the status block (saying ERROR).
  if (state_.mode != DeviceMode::measure && state_.mode != DeviceMode::error) {  // D2
    fail(event, Service::cancel_profile, FailureReason::wrong_state);
    return;
  }
  // D10: the stream stops before the reply. With no stream running the status block is the
  // answer too (D2). The mode stays MEASURE (spec 3.5).
  state_.streams.erase(event.from);
  if (state_.streams.empty()) state_.revolution_timer.reset();
  reply(event, protocol::CancelProfileReply{status_block()});
}

void ControlUnit::ensure_revolution_timer(Actions& out) {
  if (state_.streams.empty() || state_.head.speed_hz == 0) return;  // a stopped head: no revolution
  std::uint64_t due = state_.streams.begin()->second.next_revolution;
  for (const auto& [connection, stream] : state_.streams) due = std::min(due, stream.next_revolution);
  if (state_.revolution_timer && state_.revolution_timer->revolution <= due) return;
  // A profile is complete when its last point has been measured: the last point of the last
  // sector, one turn after sector 0's start minus one step (sector_geometry).
  const auto geometry = sector_geometry(state_.ram.sectors, state_.ram.global.angle_step_ticks);
  const std::uint32_t last_angle = geometry.empty() ? kTicksPerTurn : geometry.back().last_angle_unwrapped_ticks;
  const SimTime ready = revolution_time(state_.head.epoch_start, state_.head.speed_hz, due, last_angle);
  state_.revolution_timer = RevolutionTimer{arm_timer(out, ready), due};
}

void ControlUnit::emit_profiles(SimTime now, std::uint64_t revolution, const TransportQuery& transport,
                                Actions& out) {
  if (state_.mode != DeviceMode::measure || state_.streams.empty()) return;
  const std::uint16_t step = state_.ram.global.angle_step_ticks;
  const std::uint16_t speed_hz = state_.head.speed_hz;
  const SimTime epoch = state_.head.epoch_start;
  const auto geometry = sector_geometry(state_.ram.sectors, step);
  if (geometry.empty()) return;  // cannot happen in MEASURE: TRANS_MEASURE checked the table

  // D10: profiles never queue up. If the timer comes late (a slow sensor model or a stalled
  // loop let simulated time run past later revolutions), only the newest complete revolution is
  // sent; the ones in between are skipped like a busy transport's.
  const std::uint32_t last_angle = geometry.back().last_angle_unwrapped_ticks;
  std::uint64_t newest = revolution;
  while (revolution_time(epoch, speed_hz, newest + 1, last_angle) <= now) ++newest;
  for (const auto& [connection, stream] : state_.streams) {
    if (stream.next_revolution <= revolution) diagnostics_.skipped_profiles += newest - revolution;
  }
  revolution = newest;

  // Which streams get this revolution, and which skip it because their transport is still busy
  // with the previous profile (D10: PROFILECOUNT advances, PROFILESENT does not).
  std::vector<ConnectionId> receivers;
  for (const auto& [connection, stream] : state_.streams) {
    if (stream.next_revolution > revolution) continue;
    if (transport.busy(connection)) {
      ++diagnostics_.skipped_profiles;
    } else {
      receivers.push_back(connection);
    }
  }

  if (!receivers.empty()) {
    // Measure once per revolution whatever the number of streams.
    std::vector<BeamQuery> beams;
    for (const SectorGeometry& sector : geometry) {
      for (std::uint32_t i = 0; i < sector.point_count; ++i) {
        const std::uint32_t angle = sector.first_angle_unwrapped_ticks + i * step;
        beams.push_back(BeamQuery{revolution_time(epoch, speed_hz, revolution, angle), wrap_angle(angle), wrap_angle(angle)});
      }
    }
    std::vector<BeamReturn> returns(beams.size());
    const std::uint64_t revolution_number = state_.head.revolutions_before_epoch + revolution + 1;  // D3
    measurement_.measure(RevolutionQuery{revolution_number, revolution_time(epoch, speed_hz, revolution, 0)}, beams,
                         returns);
    if (state_.ram.near_field_filter_on) suppress_near_field(returns);  // D14
    if (!beam_faults_.empty()) apply_beam_faults(revolution_number, beams, returns);  // D11

    protocol::Profile profile;
    profile.profile_count = static_cast<std::uint16_t>(revolution_number);
    profile.layer = 0;
    profile.status = protocol::StatusBlock{{}, protocol::StatusByte{protocol::SensorMode::measure, protocol::MotorMode::ok}};
    std::size_t next_return = 0;
    for (const SectorGeometry& sector : geometry) {
      protocol::SectorBlock block;
      block.sector_num = sector.sector;
      block.dir_step_ticks = step;
      block.t_start_ms = state_.clock.value_at(revolution_time(epoch, speed_hz, revolution, sector.first_angle_unwrapped_ticks));
      block.t_end_ms = state_.clock.value_at(revolution_time(epoch, speed_hz, revolution, sector.last_angle_unwrapped_ticks));
      block.start_dir_ticks = wrap_angle(sector.first_angle_unwrapped_ticks);
      block.end_dir_ticks = wrap_angle(sector.last_angle_unwrapped_ticks);
      for (std::uint32_t i = 0; i < sector.point_count; ++i, ++next_return) {
        block.points.push_back(protocol::ProfilePoint{returns[next_return].distance_q8_m,
                                                      beams[next_return].angle_ticks, returns[next_return].echo});
      }
      profile.sectors.push_back(std::move(block));
    }

    for (const ConnectionId& connection : receivers) {
      ProfileStream& stream = state_.streams.at(connection);
      ++stream.profiles_sent;
      profile.format = stream.format;
      profile.profile_sent = stream.profiles_sent;
      out.telegrams.push_back(OutgoingTelegram{connection, protocol::encode_profile(profile), TelegramKind::profile});
      ++diagnostics_.profiles_sent;
      if (stream.profiles_wanted != 0 && stream.profiles_sent >= stream.profiles_wanted) {
        state_.streams.erase(connection);
      }
    }
  }
  if (!state_.streams.empty()) {
    // Next revolution for everyone already started; a later next_revolution waits its turn.
    for (auto& [connection, stream] : state_.streams) {
      if (stream.next_revolution <= revolution) stream.next_revolution = revolution + 1;
    }
    ensure_revolution_timer(out);
  }
}

}  // namespace ldoem::control
