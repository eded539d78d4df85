// The fault scheduler: which faults are active at a given simulated time, after a given
// conversation. Pure and deterministic: it reads no clock and no global random generator; a
// probability trigger draws from a counter-based stream keyed by (scene seed, entry index,
// matching-request number), so the same seed and the same conversation give the same faults
// (D11). The daemon feeds it time (advance) and requests (on_request) and asks it what to do
// to each telegram (take_wire_fault); the control socket injects and clears.
//
// Lifetime of a fault: triggered -> active (event `injected`) -> cleared (event `cleared`) when
// its duration has passed, its count is used up, a one-shot kind has acted, or clear() is
// called. A scene entry whose trigger fires again while its previous activation is still
// active starts a second activation (with its own id).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ldoem/faults/fault_spec.hpp"

namespace ldoem::faults {

using FaultId = std::uint64_t;

struct ActiveFault {
  FaultId id = 0;
  FaultSpec spec;
  SimTime since{};
  std::optional<SimTime> until;        // from duration_s
  std::optional<std::uint64_t> remaining;  // from count (wire faults: telegrams; lpt: steps)
  std::string origin;                  // "scene[2]" or "control"
  bool operator==(const ActiveFault&) const = default;
};

enum class FaultEventKind : std::uint8_t { injected, cleared };

struct FaultEvent {
  SimTime at{};
  FaultEventKind what = FaultEventKind::injected;
  FaultId id = 0;
  FaultKind kind = FaultKind::drop_reply;
  std::string reason;  // "scene[0] at_s", "control", "expired", "count used", "acted", "cleared"
  bool operator==(const FaultEvent&) const = default;
};

// The counter-based draw of probability triggers: uniform in [0, 1), a pure function.
double fault_draw(std::uint64_t seed, std::uint64_t entry_index, std::uint64_t request_number);

// D11 garbage: the `count` bytes fault `id` inserts, a pure function of (seed, id). No byte is
// 0x02, the first byte of a TCP header and the serial STX: garbage never starts a frame, so a
// host that resynchronises skips exactly these bytes.
std::vector<std::uint8_t> fault_garbage(std::uint64_t seed, std::uint64_t id, std::size_t count);

// How much of a request the daemon has seen when it calls on_request. A request that arrives in
// one piece is `whole`. A multi-frame ISO-TP request (CAN) is seen twice: at its first frame,
// which carries the service code and is where isotp_fc_overflow and isotp_fc_wait act, and when it
// is complete. Each trigger counts it once: the triggers of those two kinds at the first frame (so
// that they can refuse or hold that very request), every other trigger when it is complete.
enum class RequestSeen : std::uint8_t { whole, first_frame, rest_of_multi_frame };

// True for the kinds that act on a host's ISO-TP first frame (isotp_fc_overflow, isotp_fc_wait).
bool acts_on_host_first_frame(FaultKind kind);

class FaultScheduler {
 public:
  FaultScheduler() = default;
  FaultScheduler(std::vector<FaultSpec> scene_faults, std::uint64_t seed);

  // True when there is nothing to do now or ever (no scene entries, nothing active): the
  // daemon's fast path (D9: a scene with no faults pays nothing).
  bool idle() const { return entries_.empty() && active_.empty(); }

  // Simulated time reached `now`: at_s and TriggerNow entries fire, durations end.
  void advance(SimTime now, std::vector<FaultEvent>& events);

  // A request of `service` (request code) arrived on `transport`: on/every/probability triggers
  // (`seen`: which of them count it, above).
  void on_request(SimTime now, std::uint16_t service, Transport transport, std::vector<FaultEvent>& events,
                  RequestSeen seen = RequestSeen::whole);

  // The control socket's inject-fault: the entry's trigger is ignored except at_s (later).
  FaultId inject(SimTime now, FaultSpec spec, std::vector<FaultEvent>& events);
  // False when no fault has that id.
  bool clear(SimTime now, FaultId id, std::vector<FaultEvent>& events);
  // clear-fault with no id, and a power cycle's end: every active fault.
  void clear_all(SimTime now, std::string_view reason, std::vector<FaultEvent>& events);

  // The first active wire fault of `kind` matching the telegram (transport, request code of the
  // reply), or nothing. Using it counts one telegram against its count.
  // `service` empty: a fault of the connection (tcp_stall, ISO-TP flow control, the LPT), whatever
  // service the entry names.
  std::optional<ActiveFault> take_wire_fault(SimTime now, FaultKind kind, Transport transport,
                                             std::optional<std::uint16_t> service, std::vector<FaultEvent>& events);
  // Like take_wire_fault for any of the wire kinds of `transport`, first in activation order.
  std::optional<ActiveFault> take_any_wire_fault(SimTime now, Transport transport, std::uint16_t service,
                                                 std::vector<FaultEvent>& events);
  // A one-shot or device fault that has acted: cleared with reason "acted".
  void acted(SimTime now, FaultId id, std::vector<FaultEvent>& events);

  const std::vector<ActiveFault>& active() const { return active_; }
  bool is_active(FaultKind kind) const;
  const ActiveFault* find_active(FaultKind kind) const;
  // The first active fault of `kind` on `transport` at `now` (not expired), whatever its service;
  // nothing is counted (tcp_stall, bandwidth, isotp_fc_wait, lpt_jam last as long as they are active).
  const ActiveFault* find_active_on(SimTime now, FaultKind kind, Transport transport) const;
  std::uint64_t seed() const { return seed_; }
  // The earliest time at which advance() has something to do, if any.
  std::optional<SimTime> next_deadline() const;

 private:
  struct Entry {
    FaultSpec spec;
    std::uint64_t index = 0;
    bool fired = false;                 // at_s / now entries fire once
    std::uint64_t matching_requests = 0;  // on/every/probability counter
  };
  void activate(SimTime now, FaultSpec spec, std::string origin, std::vector<FaultEvent>& events);
  void remove_at(std::size_t position, SimTime now, std::string reason, std::vector<FaultEvent>& events);
  bool matches(const ActiveFault& fault, Transport transport, std::optional<std::uint16_t> service) const;

  std::vector<Entry> entries_;
  std::vector<ActiveFault> active_;
  std::uint64_t seed_ = 0;
  FaultId next_id_ = 1;
};

}  // namespace ldoem::faults
