// What the control unit exchanges with the rest of the daemon: who a telegram comes from, what
// it asks the daemon to do, and the three questions it asks the outside world (head spin-up,
// ranges, transport back-pressure). Everything here is a value or a small interface, so that
// tests use fakes and the daemon wires the real models (design.md conventions 2 and 4).
#pragma once

#include <compare>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/config.hpp"
#include "ldoem/protocol/transport.hpp"
#include "ldoem/base/sim_time.hpp"

namespace ldoem::control {

using base::SimTime;

// Who a telegram came from: a host connection on one transport (protocol/transport.hpp). TCP
// and serial telegrams are capped at 5816 payload bytes, ISO-TP over CAN is not (D3).
using protocol::ConnectionId;
using protocol::Transport;

// Names a timer the control unit asked for. The daemon calls on_timer(at, id) once simulated
// time reaches `at`; ids never repeat. A timer the control unit no longer wants is named in
// Actions::cancelled_timers: with a virtual clock (D7) a stale deadline left queued would move
// simulated time for nothing. (One that fires anyway is ignored.)
struct TimerId {
  std::uint64_t value = 0;
  auto operator<=>(const TimerId&) const = default;
};

enum class TelegramKind : std::uint8_t {
  reply,    // the answer to a request (or SERVICE_FAILURE)
  profile,  // a 0x8301 profile telegram of a running GET_PROFILE
};

// One telegram payload (service code WORD first, no framing) for one connection. The daemon
// frames it and writes it in one piece (D10).
struct OutgoingTelegram {
  ConnectionId to;
  protocol::Bytes payload;
  TelegramKind kind = TelegramKind::reply;
  bool operator==(const OutgoingTelegram&) const = default;
};

struct TimerRequest {
  SimTime at{};
  TimerId id;
  bool operator==(const TimerRequest&) const = default;
};

// Everything one event makes the daemon do, in order: send `telegrams` in vector order, drop
// `cancelled_timers`, arm `timers`. `flash_image` is the image this event wrote to flash, already
// stored through ControlUnit::Setup::flash_store.
// The daemon is told what changed; it never compares the unit's state after an event:
// - head_target_hz: the head's target speed changed at this event's time (a spin-up began, or
//   the head stopped); the D9 head_dynamics model follows it.
// - can_config: the CAN configuration in RAM changed (SET_CONFIG key 2, a reset to flash, D1);
//   the CAN endpoint moves the first pair and its BS/STmin. The reply that confirmed it is
//   already in `telegrams` and leaves on the old identifiers.
struct Actions {
  std::vector<OutgoingTelegram> telegrams;
  std::vector<TimerId> cancelled_timers;
  std::vector<TimerRequest> timers;
  std::optional<protocol::Bytes> flash_image;
  std::optional<std::uint16_t> head_target_hz;
  std::optional<protocol::CanConfig> can_config;
  bool operator==(const Actions&) const = default;
};

// The LD's own head motor (D7): how long a speed change takes. Speeds in revolutions per
// second; from_hz is 0 for a stopped head. The default daemon wiring integrates the HeadConfig
// of the scene; tests use a constant.
class HeadModel {
 public:
  virtual ~HeadModel() = default;
  virtual SimTime time_to_reach(double from_hz, double to_hz) const = 0;
};

// One point the control unit wants measured.
struct BeamQuery {
  SimTime time{};                 // when the beam fires (revolution start + angle / 5760 * period)
  std::uint16_t angle_ticks = 0;  // head angle, 1/16 deg, 0 = +x, counter-clockwise (D5)
  // Stable identity of the beam within its revolution for counter-based noise (D6): the head
  // angle in ticks, so it does not depend on how the sector table splits the turn.
  std::uint32_t beam_index = 0;
};

struct BeamReturn {
  std::uint16_t distance_q8_m = 0;  // 1/256 m; 0 = no echo (D3)
  std::uint16_t echo = 0;
  bool operator==(const BeamReturn&) const = default;
};

// One revolution the control unit wants measured: PROFILECOUNT's count (revolutions since
// power-up, from 1, D3) without the 16-bit wrap, and when the revolution began (angle 0).
struct RevolutionQuery {
  std::uint64_t number = 0;
  SimTime start{};
};

// The sensor model as the control unit sees it: ranges for the given beams of one revolution.
// Called once per revolution whatever number of streams run; returns.size() == beams.size().
class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;
  virtual void measure(const RevolutionQuery& revolution, std::span<const BeamQuery> beams,
                       std::span<BeamReturn> returns) = 0;
};

// The transport's answer to "is this connection still sending the previous profile?", asked
// when a profile is due (D10: such a revolution is skipped for that connection).
class TransportQuery {
 public:
  virtual ~TransportQuery() = default;
  virtual bool busy(ConnectionId connection) const = 0;
};

}  // namespace ldoem::control
