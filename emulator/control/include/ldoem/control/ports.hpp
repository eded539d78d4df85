// What the control unit exchanges with the rest of the daemon: who a telegram comes from, what
// it asks the daemon to do, and the three questions it asks the outside world (head spin-up,
// ranges, transport back-pressure). Everything here is a value or a small interface, so that
// tests use fakes and the daemon wires the real models (STYLE.md sections 2 and 4).
#pragma once

#include <compare>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/sim_time.hpp"

namespace ldoem::control {

using protocol::SimTime;

// The transport a connection uses. TCP and serial telegrams are capped at 5816 payload bytes,
// ISO-TP over CAN is not (D3).
enum class TransportKind : std::uint8_t { tcp, serial, can };

// One host connection (a TCP session, a serial line, a CAN identifier pair). `index` is the
// daemon's number for it, unique per kind while the connection lives.
struct ConnectionId {
  TransportKind kind = TransportKind::tcp;
  std::uint32_t index = 0;
  auto operator<=>(const ConnectionId&) const = default;
};

std::string to_string(ConnectionId connection);

// Names a timer the control unit asked for. The daemon calls on_timer(at, id) once simulated
// time reaches `at`; ids never repeat, and a timer the control unit no longer wants is simply
// ignored when it fires, so the daemon never has to cancel one.
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

// Everything one event makes the daemon do, in order: send `telegrams` in vector order, arm
// `timers`, and if `flash_image` is set, store it (FlashStore::save).
struct Actions {
  std::vector<OutgoingTelegram> telegrams;
  std::vector<TimerRequest> timers;
  std::optional<protocol::Bytes> flash_image;
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

// The sensor model as the control unit sees it: ranges for the given beams of one revolution.
// `revolution` is PROFILECOUNT's count (revolutions since power-up, from 1, D3) without the
// 16-bit wrap. Called once per revolution whatever number of streams run; returns.size() ==
// beams.size().
class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;
  virtual void measure(std::uint64_t revolution, std::span<const BeamQuery> beams,
                       std::span<BeamReturn> returns) = 0;
};

// The transport's answer to "is this connection still sending the previous profile?", asked
// when a profile is due (D10: such a revolution is skipped for that connection).
class TransportQuery {
 public:
  virtual ~TransportQuery() = default;
  virtual bool busy(ConnectionId connection) const = 0;
};

// A TransportQuery that is never busy: for callers that have no back-pressure to report.
class NeverBusy final : public TransportQuery {
 public:
  bool busy(ConnectionId) const override { return false; }
};

}  // namespace ldoem::control
